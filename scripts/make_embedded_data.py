"""Rebuild data/models/ (the embedded default objects) from Debian's sweethome3d-furniture.

Run once by a maintainer (``apt-get install sweethome3d-furniture``); the result is
committed. Every model comes from the CC0 BlendSwap-CC-0 library; its licence note and
each model's own licence file are copied along.

    .venv/bin/python scripts/make_embedded_data.py
"""

import shutil
import zipfile
from pathlib import Path

import pandas as pd

from heatdata.io.sh3f import sh3f_entries

SH3F = Path("/usr/share/sweethome3d/furniture/BlendSwap-CC-0.sh3f")
OUT = Path(__file__).resolve().parents[1] / "data" / "models"

# model folder -> (object id, class, scale applied to the catalogue size, note)
SELECTION = {
    "plasticCup": ("plastic-cup", "cup", 1.0, ""),
    "caffe_final": ("coffee-cup", "cup", 1.0, "cup on a saucer, with handle"),
    "beerGlass": ("beer-mug", "mug", 1.0, "glass mug with handle"),
    "cosmeticsPot": ("cosmetics-pot", "jar", 1.0, ""),
    "mamadeira": ("baby-bottle", "bottle", 1.0, ""),
    "yogurtBottle": ("yogurt-bottle", "bottle", 1.0, ""),
    "tetrapak": ("milk-carton", "box", 1.0, ""),
    "speaker2": ("speaker-small", "box", 0.5, "half the catalogue size, a mini speaker, so it fits the 1 m view"),
    "speaker3": ("speaker-tall", "box", 0.5, "half the catalogue size, a mini speaker, so it fits the 1 m view"),
    "butter": ("butter-dish", "box", 1.0, ""),
    "kalender": ("desk-calendar", "calendar", 1.0, ""),
    "woodToy": ("wood-toy", "toy", 1.0, ""),
    "cupcake": ("cupcake", "food", 1.0, ""),
    "bread": ("bread", "food", 1.0, ""),
}


def main() -> None:
    entries = sh3f_entries(SH3F)
    entries["folder"] = entries["model"].map(lambda m: Path(m).parent.name)
    if OUT.exists():
        shutil.rmtree(OUT)
    OUT.mkdir(parents=True)
    rows = []
    with zipfile.ZipFile(SH3F) as archive:
        archive.extract("LICENSE.TXT", OUT)
        (OUT / "LICENSE.TXT").rename(OUT / "LICENSE-BlendSwap-CC-0.txt")
        names = archive.namelist()
        for folder, (object_id, label, scale, note) in SELECTION.items():
            entry = entries[entries["folder"] == folder].iloc[0]
            prefix = str(Path(entry.model).parent) + "/"
            for member in (n for n in names if n.startswith(prefix) and not n.endswith("/")):
                target = OUT / object_id / Path(member).name
                target.parent.mkdir(exist_ok=True)
                target.write_bytes(archive.read(member))
            rows.append(
                {
                    "object": object_id,
                    "label": label,
                    "file": f"{object_id}/{Path(entry.model).name}",
                    "width": round(entry.width * scale, 4),
                    "height": round(entry.height * scale, 4),
                    "depth": round(entry.depth * scale, 4),
                    "rotation": entry.rotation,
                    "name": entry["name"] + (f" ({note})" if note else ""),
                    "source": f"Sweet Home 3D BlendSwap-CC-0 library, {entry.creator}",
                    "licence": "CC0-1.0",
                }
            )
    pd.DataFrame(rows).to_csv(OUT / "catalog.csv", index=False)
    print(f"wrote {len(rows)} models to {OUT}")


if __name__ == "__main__":
    main()

"""The workflow's report: its figures and its summary (rule report_figures)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import yaml

from .catalog import read_catalog
from .descriptors import file_name
from .figures import RENDERED_NOTE, draw_example_views, plot_confusion, plot_isomap, plot_precision, plot_view_confusion
from .tables import read_table
from .version import __version__


def draw_report(descriptors_path, predictions_path, precision_path, catalog_path, output, *, primary: str,
                config: dict) -> None:
    """Workflow step: the report's figures and summary.

    ``output`` has ``precision, confusion, isomap, views, global_derivative, summary``. The
    confusion folder holds one object confusion matrix per descriptor and library size.
    """
    counts, _ = read_table(descriptors_path, columns=["object", "view_id", "n_vertices"])
    predictions, _ = read_table(predictions_path)
    precision = pd.read_csv(precision_path)
    plot_precision(precision, output.precision)
    Path(output.confusion).mkdir(parents=True, exist_ok=True)
    for (name, size), rows in predictions.groupby(["descriptor", "library_size"]):
        plot_confusion(rows, Path(output.confusion) / f"{file_name(name)}_{size:03d}_views.png",
                       f"{name}, {size} library views per object")
    chosen = predictions[predictions["descriptor"] == primary]
    largest = chosen[chosen["library_size"] == chosen["library_size"].max()]
    plot_view_confusion(largest, Path(output.confusion) / "view_angles.png", primary)
    library, _ = read_table(descriptors_path, columns=["descriptor", "kind", "object", "split", "azimuth", "values"],
                            filters=[("descriptor", "==", primary), ("split", "==", "train")])
    plot_isomap(library, primary, output.isomap)
    views = config["views"]
    draw_example_views(read_catalog(catalog_path), output.views, elevation=views["elevation"],
                       distance=views["distance"], noise=views["noise"], seed=views["seed"],
                       image_scale=views.get("image_scale", 1.0), derivative_path=output.global_derivative)
    table = precision[(precision["group"] == "all")].pivot_table(
        index=["level", "descriptor"], columns="library_size", values="precision")
    Path(output.summary).write_text("\n".join([
        "# heatdata run", "", RENDERED_NOTE, "", *class_note(read_catalog(catalog_path)),
        f"- heatdata {__version__}; {counts['object'].nunique()} objects, "
        f"{counts['view_id'].nunique()} views (mean "
        f"{counts.drop_duplicates('view_id')['n_vertices'].mean():.0f} vertices)",
        f"- views: {views}",
        "", "## Precision (columns: library views per object)", "",
        table.map(lambda v: f"{v:.1%}").to_markdown(), "",
        "## Run parameters", "", "```yaml", yaml.safe_dump(dict(config), sort_keys=False).strip(), "```", "",
    ]))


def class_note(catalog: pd.DataFrame) -> list[str]:
    """The summary's lines on classes: when every class holds one object, class precision is object precision."""
    per_class = catalog.groupby("label")["object"].nunique()
    if per_class.max() == 1:
        return [f"Each of the {len(per_class)} classes holds one object: the run recognizes objects, and class "
                "precision equals object precision.", ""]
    lonely = sorted(per_class[per_class == 1].index)
    if lonely:
        return [f"Classes with one object ({', '.join(lonely)}): their class precision equals their object "
                "precision.", ""]
    return []

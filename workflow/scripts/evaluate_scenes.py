"""The scenes' detection, naming, poses and latency per library, the off-axis precision, the known/unknown curve, and
the overlays and report page (rule evaluate_scenes)."""

import io
from pathlib import Path

import pandas as pd

from heatdata.experiments.scenes import offaxis_precision, read_scene, scene_summary
from heatdata.io.tables import read_table
from heatdata.log import setup_logging
from heatdata.recognition.pose import read_surface
from heatdata.reporting.figures.scenes import frame_image, known_curve, overlay_image, row_marks
from heatdata.reporting.pages import scenes_page

setup_logging(path=snakemake.log[0])
scores = pd.concat([read_table(path)[0] for path in snakemake.input.detections], ignore_index=True)
summary = scene_summary(scores)
summary.to_csv(snakemake.output.summary, index=False)
if snakemake.input.offaxis:
    library, _ = read_table(snakemake.input.library, filters=[("split", "==", "train")])
    moved = pd.concat([read_table(path)[0] for path in snakemake.input.offaxis], ignore_index=True)
    predictions, _ = read_table(snakemake.input.predictions)
    offaxis = offaxis_precision(library, moved, predictions, snakemake.params.size, snakemake.params.time_rule)
else:
    offaxis = offaxis_precision(pd.DataFrame(), pd.DataFrame(), pd.DataFrame(), snakemake.params.size, "every")
offaxis.to_csv(snakemake.output.offaxis, index=False)
primary = scores[scores["descriptor"] == snakemake.params.primary]
surfaces = {obj: read_surface(p) for obj, p in zip(snakemake.params.objects, snakemake.input.surfaces, strict=True)}
overlays = {}
for path in snakemake.output.overlays:
    scene = Path(path).stem
    depth, rgb, intrinsics, _, _ = read_scene(Path(snakemake.input.frames[0]).parent / f"{scene}.png")
    marks = row_marks(primary[primary["scene"] == scene], depth.shape, surfaces, intrinsics)
    picture = overlay_image(frame_image(depth, rgb), marks)
    picture.save(path)
    buffer = io.BytesIO()
    picture.save(buffer, format="PNG")
    overlays[scene] = buffer.getvalue()
with open(snakemake.output.page, "w") as out:
    page = scenes_page(
        summary, offaxis, overlays, snakemake.params.settings, snakemake.params.primary, known_curve(primary)
    )
    out.write(page)

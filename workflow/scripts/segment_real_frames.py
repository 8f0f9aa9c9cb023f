"""A folder of labelled real frames segmented and scored frame by frame, and its three worst frames drawn (rule
segment_real_frames)."""

from heatdata.experiments.real_frames import read_labelled_frames, score_folder, worst_frames
from heatdata.log import setup_logging
from heatdata.reporting.figures.real_frames import draw_frames
from heatdata.segmentation.score import score_segmentation
from heatdata.segmentation.segment import label_image, segment_frame
from heatdata.segmentation.settings import SegmentSettings

setup_logging(path=snakemake.log[0])
options = snakemake.params.settings
settings = SegmentSettings(
    concavity=options["concavity"], cluster_distance=options["cluster_distance"], min_pixels=options["min_pixels"]
)
scores = score_folder(snakemake.params.folder, settings)
scores.to_csv(snakemake.output.scores, index=False)
worst = set(worst_frames(scores)["frame"])
rows = []
for frame in read_labelled_frames(snakemake.params.folder):
    if frame.name in worst:
        found = segment_frame(frame.depth, frame.intrinsics, frame.rgb, settings, name=frame.name)
        labels = label_image(found, frame.depth.shape)
        rows.append((frame, labels, score_segmentation(labels, frame.truth)))
draw_frames(rows, snakemake.output.worst)

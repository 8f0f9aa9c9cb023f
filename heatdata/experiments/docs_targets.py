"""The ``docs_*`` targets: which run each reads, and the steps that write its tables and figures.

``workflow/rules/docs.smk`` makes one Snakemake rule of each, which runs its steps with
:func:`heatdata.experiments.publish.publish`; the tests read this table to dry-run every target.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

from heatdata.descriptors import DEFAULT_DESCRIPTOR, file_name

E = "config/experiments"


def csv(name: str) -> str:
    """A published table's path."""
    return f"docs/results/{name}.csv"


def png(name: str) -> str:
    """A published figure's path."""
    return f"docs/images/{name}.png"


def script(name: str, *arguments: str) -> dict:
    """A step that runs ``scripts/<name>.py`` with ``arguments``."""
    return {"script": [f"scripts/{name}.py", *arguments]}


VALUE_SCALES = [
    "--descriptor",
    "pvhk/polar/center/64",
    "ft-pvhk/polar/center/64",
    "pvst/polar/interior/64/T0.75",
    "--transform",
    "x1",
    "x0.3",
    "x0.1",
    "x0.01",
    "log10",
    "log10x0.3",
    "log10x0.1",
]
#: the multi-view ablations' run and settings on the chairs (``multiview_chairs.yaml``'s library and path)
CHAIRS_ABLATION = (
    *("multiview_ablation", "--results", "results/multiview_chairs", "--library-views", "13", "7"),
    *("--sigma", "0.2", "--tau", "0.5", "--starts", "10", "--max-degrees", "360"),
)
RESOLUTIONS = {"320x240, 2.5 m": "results/chairs_12", "640x480, 1.5 m": "results/chairs_12_640"}
PEOPLE_RUNS = {
    "seed 0": "results/people",
    "seed 1": "results/people_seed1",
    "seed 2": "results/people_seed2",
    "seed 0, 640x480": "results/people_640",
}
#: the main job's libraries the open-set evaluation reads (every kind but the time-scaled FT-PVHK)
OPEN_SET = [
    "pvhk_polar_center_64",
    "pvhk_arclength_closest_64",
    "c-pvhk_polar_center_64_c3",
    "c-pvhk_polar_center_64_sat-hue_shape-clock",
    "pvst_polar_interior_64_T0.75",
    "hgd_color=hue-saturation",
]
#: the library file the poses are measured with: the default descriptor's, 40 views an object
DEFAULT_LIBRARY = f"{file_name(DEFAULT_DESCRIPTOR.name)}-40.parquet"
RUMP = "results/rump_proxy"  # the proxy's intermediate tables (scripts/rump_proxy.py reads no run)


class Target(NamedTuple):
    """A ``docs_*`` target: the results folder of the run it publishes (None: it reads no run), its config files,
    its inputs, the files it writes into docs/ and the steps of :func:`publish` that write them."""

    results: str | None
    configs: list[str]
    inputs: list[str]
    outputs: list[str]
    steps: list[dict]


def targets(objects: Sequence[str], results: str) -> dict[str, Target]:
    """Every ``docs_*`` target of ``workflow/rules/docs.smk``; ``objects`` and ``results`` are the current run's (the
    rendered views of a run are inputs only when it is the current one)."""

    def views_of(run: str) -> list[str]:
        return [f"{run}/views/{obj}.parquet" for obj in objects] if run == results else []

    table: dict[str, tuple[str | None, list[str], list[str], list[str], list[dict]]] = {
        "docs_main": (
            "results",
            ["config/config.yaml"],
            ["results/figures/views.png", "results/descriptors.parquet", *views_of("results")],
            [png("views"), csv("household_ft_time_scales"), csv("household_value_scales"), csv("household_steps")],
            [
                {"copy": ["results/figures/views.png", png("views")]},
                script(
                    "ft_time_scales",
                    "results/descriptors.parquet",
                    "ft-pvhk/polar/center/64",
                    "--out",
                    csv("household_ft_time_scales"),
                ),
                script(
                    "value_scales", "results/descriptors.parquet", *VALUE_SCALES, "--out", csv("household_value_scales")
                ),
                script("complex_ablation", "results", "--out", csv("household_steps")),
            ],
        ),
        "docs_demo": (
            None,
            [],
            [],
            [png("confusion_objects")],
            [
                {"script": ["-m", "heatdata.cli", "demo", "--out", "results/demo"]},
                {"copy": ["results/demo/confusion_objects_pvhk_polar_center_64.png", png("confusion_objects")]},
            ],
        ),
        "docs_chairs": (
            "results/chairs",
            [f"{E}/chairs.yaml"],
            [
                "results/chairs/figures/precision.png",
                "results/chairs/figures/global_derivative.png",
                "results/chairs/descriptors.parquet",
            ],
            [
                png("chairs_precision"),
                png("chairs_global_derivative"),
                csv("chairs_protocols"),
                csv("chairs_ft_time_scales"),
                csv("chairs_value_scales"),
                csv("chairs_combined"),
            ],
            [
                {"copy": ["results/chairs/figures/precision.png", png("chairs_precision")]},
                {"copy": ["results/chairs/figures/global_derivative.png", png("chairs_global_derivative")]},
                script("protocols", "results/chairs/descriptors.parquet", "--out", csv("chairs_protocols")),
                script(
                    "ft_time_scales",
                    "results/chairs/descriptors.parquet",
                    "ft-pvhk/polar/center/64",
                    "--out",
                    csv("chairs_ft_time_scales"),
                ),
                script(
                    "value_scales",
                    "results/chairs/descriptors.parquet",
                    *VALUE_SCALES,
                    "--leave-one-out",  # its leave-one-out rows (library size 0); the household table has none
                    "--out",
                    csv("chairs_value_scales"),
                ),
                script(
                    "combine_kinds",
                    "results/chairs/descriptors.parquet",
                    "--descriptor",
                    "esf",
                    "pvst/polar/interior/64/T0.75/log-time",
                    "--out",
                    csv("chairs_combined"),
                ),
            ],
        ),
        "docs_chairs_12": (
            "results/chairs_12",
            [f"{E}/chairs.yaml", f"{E}/chairs_12.yaml"],
            [
                "results/chairs_12/evaluation/precision.csv",
                "results/chairs_12/descriptors.parquet",
                *views_of("results/chairs_12"),
            ],
            [
                csv("chairs_12_precision"),
                csv("chairs_12_steps"),
                csv("chairs_12_combined"),
                csv("chairs_12_colour_share"),
            ],
            [
                {"precision": ["results/chairs_12/evaluation/precision.csv", csv("chairs_12_precision")]},
                script("complex_ablation", "results/chairs_12", "--out", csv("chairs_12_steps")),
                script(
                    "combine_kinds",
                    "results/chairs_12/descriptors.parquet",
                    "--descriptor",
                    "esf",
                    "pvst/polar/interior/64/T0.75/log-time",
                    "--out",
                    csv("chairs_12_combined"),
                ),
                script("color_share", "results/chairs_12/descriptors.parquet", "--out", csv("chairs_12_colour_share")),
            ],
        ),
        "docs_chairs_12_640": (
            "results/chairs_12_640",
            [f"{E}/chairs.yaml", f"{E}/chairs_12.yaml", f"{E}/chairs_640.yaml"],
            [f"{run}/descriptors.parquet" for run in RESOLUTIONS.values()],
            [csv("chairs_12_resolution"), csv("chairs_12_ft_time_scales")],
            [
                *(
                    script(
                        "protocols",
                        f"{run}/descriptors.parquet",
                        "--out",
                        f"results/chairs_12_640/published/protocols_{k}.csv",
                    )
                    for k, run in enumerate(RESOLUTIONS.values())
                ),
                *(
                    script(
                        "ft_time_scales",
                        f"{run}/descriptors.parquet",
                        "ft-pvhk/polar/center/64",
                        "--out",
                        f"results/chairs_12_640/published/ft_time_scales_{k}.csv",
                    )
                    for k, run in enumerate(RESOLUTIONS.values())
                ),
                {
                    "labelled": [
                        "views",
                        {
                            label: f"results/chairs_12_640/published/protocols_{k}.csv"
                            for k, label in enumerate(RESOLUTIONS)
                        },
                        csv("chairs_12_resolution"),
                    ]
                },
                {
                    "labelled": [
                        "views",
                        {
                            label: f"results/chairs_12_640/published/ft_time_scales_{k}.csv"
                            for k, label in enumerate(RESOLUTIONS)
                        },
                        csv("chairs_12_ft_time_scales"),
                    ]
                },
            ],
        ),
        "docs_chairs_12_sampling": (
            "results/chairs_12_sampling",
            [f"{E}/chairs.yaml", f"{E}/chairs_12.yaml", f"{E}/chairs_12_sampling.yaml"],
            ["results/chairs_12_sampling/evaluation/precision.csv"],
            [csv("chairs_12_sampling")],
            [{"precision": ["results/chairs_12_sampling/evaluation/precision.csv", csv("chairs_12_sampling")]}],
        ),
        "docs_compact_chairs": (
            "results/compact_chairs",
            [f"{E}/compact_chairs.yaml"],
            ["results/compact_chairs/figures/compact_precision.png"],
            [png("compact_chairs_precision")],
            [{"copy": ["results/compact_chairs/figures/compact_precision.png", png("compact_chairs_precision")]}],
        ),
        "docs_compact_chairs_pvst": (
            "results/compact_chairs_pvst",
            [f"{E}/compact_chairs.yaml", f"{E}/compact_chairs_pvst.yaml"],
            [
                "results/compact_chairs_pvst/compact/precision.csv",
                "results/compact_chairs_pvst/figures/compact_precision.png",
            ],
            [csv("compact_chairs_pvst"), png("compact_chairs_pvst_precision")],
            [
                {
                    "compact": [
                        "results/compact_chairs_pvst/compact/precision.csv",
                        "pvst/polar/interior/64/T0.75",
                        csv("compact_chairs_pvst"),
                    ]
                },
                {
                    "copy": [
                        "results/compact_chairs_pvst/figures/compact_precision.png",
                        png("compact_chairs_pvst_precision"),
                    ]
                },
            ],
        ),
        "docs_compact_chairs_pvst_thesis": (
            "results/compact_chairs_pvst_thesis",
            [f"{E}/compact_chairs.yaml", f"{E}/compact_chairs_pvst.yaml", f"{E}/compact_chairs_pvst_thesis.yaml"],
            ["results/compact_chairs_pvst_thesis/compact/precision.csv"],
            [csv("compact_chairs_pvst_thesis")],
            [
                {
                    "compact": [
                        "results/compact_chairs_pvst_thesis/compact/precision.csv",
                        "pvst/polar/interior/64/T0.75 (c: mhd, rho: l2)",
                        csv("compact_chairs_pvst_thesis"),
                    ]
                }
            ],
        ),
        "docs_compact_chairs_small": (
            "results/compact_chairs_pvst_small",
            [
                f"{E}/compact_chairs.yaml",
                f"{E}/compact_chairs_pvst.yaml",
                f"{E}/compact_chairs_small.yaml",
                f"{E}/compact_chairs_pvst_small.yaml",
            ],
            [
                "results/compact_chairs_small/compact/precision.csv",
                "results/compact_chairs_pvst_small/compact/precision.csv",
            ],
            [csv("compact_chairs_pvst_small")],
            [
                {
                    "compact": [
                        "results/compact_chairs_small/compact/precision.csv",
                        "pvhk/polar/center/64",
                        "results/compact_chairs_pvst_small/published/pvhk.csv",
                    ]
                },
                {
                    "compact": [
                        "results/compact_chairs_pvst_small/compact/precision.csv",
                        "pvst/polar/interior/64/T0.75",
                        "results/compact_chairs_pvst_small/published/pvst.csv",
                    ]
                },
                {
                    "labelled": [
                        "run",
                        {
                            "compact_chairs_small": "results/compact_chairs_pvst_small/published/pvhk.csv",
                            "compact_chairs_pvst_small": "results/compact_chairs_pvst_small/published/pvst.csv",
                        },
                        csv("compact_chairs_pvst_small"),
                    ]
                },
            ],
        ),
        "docs_compact_cups": (
            "results/compact_cups",
            [f"{E}/compact_cups.yaml"],
            ["results/compact_cups/figures/compact_precision.png"],
            [png("compact_cups_precision")],
            [{"copy": ["results/compact_cups/figures/compact_precision.png", png("compact_cups_precision")]}],
        ),
        "docs_baselines": (
            "results/baselines",
            [f"{E}/baselines.yaml"],
            [
                "results/baselines/evaluation/precision.csv",
                "results/baselines/comparison/holes.csv",
                "results/baselines/figures/holes.png",
                "results/baselines/figures/isomap_descriptors.png",
            ],
            [csv("baselines_precision"), csv("baselines_holes"), png("holes"), png("isomap_descriptors")],
            [
                {"copy": ["results/baselines/evaluation/precision.csv", csv("baselines_precision")]},
                {"copy": ["results/baselines/comparison/holes.csv", csv("baselines_holes")]},
                {"copy": ["results/baselines/figures/holes.png", png("holes")]},
                {"copy": ["results/baselines/figures/isomap_descriptors.png", png("isomap_descriptors")]},
            ],
        ),
        "docs_baselines_28": (
            "results/baselines_28",
            [f"{E}/baselines.yaml", f"{E}/baselines_28.yaml"],
            ["results/baselines_28/evaluation/precision.csv"],
            [csv("baselines_28_precision")],
            [{"precision": ["results/baselines_28/evaluation/precision.csv", csv("baselines_28_precision")]}],
        ),
        "docs_multiview": (
            "results/multiview",
            [f"{E}/multiview.yaml"],
            [
                "results/multiview/multiview/summary.csv",
                "results/multiview/figures/multiview.png",
                "results/multiview/descriptors.parquet",
            ],
            [csv("multiview_cups_speakers"), png("multiview"), csv("multiview_ablation")],
            [
                {"copy": ["results/multiview/multiview/summary.csv", csv("multiview_cups_speakers")]},
                {"copy": ["results/multiview/figures/multiview.png", png("multiview")]},
                script("multiview_ablation", "--results", "results/multiview", "--out", csv("multiview_ablation")),
            ],
        ),
        "docs_multiview_chairs": (
            "results/multiview_chairs",
            [f"{E}/multiview_chairs.yaml"],
            [
                "results/multiview_chairs/multiview/summary.csv",
                "results/multiview_chairs/figures/multiview.png",
                "results/multiview_chairs/descriptors.parquet",
            ],
            [
                csv("multiview_chairs"),
                png("multiview_chairs"),
                csv("multiview_chairs_newcomers"),
                csv("multiview_chairs_alpha"),
            ],
            [
                {"copy": ["results/multiview_chairs/multiview/summary.csv", csv("multiview_chairs")]},
                {"copy": ["results/multiview_chairs/figures/multiview.png", png("multiview_chairs")]},
                script(
                    *CHAIRS_ABLATION,
                    *("--particles", "16", "40", "160", "--newcomer", "mean", "least", "--repopulate", "cell", "view"),
                    *("--policies", "fixed", "--repetitions", "3", "--out", csv("multiview_chairs_newcomers")),
                ),
                script(
                    *CHAIRS_ABLATION,
                    *("--particles", "16", "80", "--alpha", "learned", "3", "1", "--repetitions", "2"),
                    *("--out", csv("multiview_chairs_alpha")),
                ),
            ],
        ),
        "docs_people": (
            "results/people",
            [f"{E}/people.yaml"],
            [f"{run}/people/{table}.csv" for run in PEOPLE_RUNS.values() for table in ("poses", "twins")]
            + ["results/people/figures/people_poses.png", "results/people/figures/people_twins.png"],
            [csv("people_poses"), csv("people_twins"), png("people_poses"), png("people_twins")],
            [
                {
                    "labelled": [
                        "run",
                        {label: f"{run}/people/poses.csv" for label, run in PEOPLE_RUNS.items()},
                        csv("people_poses"),
                    ]
                },
                {
                    "labelled": [
                        "run",
                        {label: f"{run}/people/twins.csv" for label, run in PEOPLE_RUNS.items()},
                        csv("people_twins"),
                    ]
                },
                {"copy": ["results/people/figures/people_poses.png", png("people_poses")]},
                {"copy": ["results/people/figures/people_twins.png", png("people_twins")]},
            ],
        ),
        "docs_twins": (
            "results/twins",
            [f"{E}/twins.yaml"],
            ["results/twins/evaluation/predictions.parquet", "results/twins/catalog.csv"],
            [csv("twins_precision"), png("colour_twins")],
            [script("color_twins", "results/twins", "--out", csv("twins_precision"), "--figure", png("colour_twins"))],
        ),
        "docs_jasnom_cuts": (
            None,
            [],
            [],
            [csv("jasnom_cuts"), csv("jasnom_holes")],
            [script("jasnom_cuts", "--out", csv("jasnom_cuts"), "--holes-out", csv("jasnom_holes"))],
        ),
        "docs_jasnom_scans": (
            None,
            [],
            [],
            [csv("jasnom_scans"), csv("jasnom_scans_precision"), csv("jasnom_scans_tried"), png("jasnom")],
            [
                script(
                    "jasnom_scans",
                    "--out",
                    csv("jasnom_scans"),
                    "--precision-out",
                    csv("jasnom_scans_precision"),
                    "--tried-out",
                    csv("jasnom_scans_tried"),
                    "--figure",
                    png("jasnom"),
                )
            ],
        ),
        "docs_rump": (
            None,
            [],
            [],
            [csv("rump_proxy"), csv("rump_proxy_ablation"), png("rump_proxy")],
            [
                script(
                    "rump_proxy",
                    "--out",
                    csv("rump_proxy"),
                    "--ablation-out",
                    f"{RUMP}/ablation.csv",
                    "--figure",
                    png("rump_proxy"),
                ),
                script(
                    "rump_proxy",
                    "--image-scale",
                    "0.5",
                    "--out",
                    f"{RUMP}/bodies_320.csv",
                    "--ablation-out",
                    f"{RUMP}/ablation_320.csv",
                ),
                script(
                    "rump_proxy",
                    "--muscle",
                    "0.5,0.5",
                    "--ablation",
                    "1.5",
                    "--out",
                    f"{RUMP}/bodies_muscle.csv",
                    "--ablation-out",
                    f"{RUMP}/ablation_muscle.csv",
                ),
                {
                    "concat": [
                        [f"{RUMP}/ablation.csv", f"{RUMP}/ablation_320.csv", f"{RUMP}/ablation_muscle.csv"],
                        csv("rump_proxy_ablation"),
                    ]
                },
            ],
        ),
        "docs_canonical": (  # the centre the canonical frame faces, on the main job's views
            "results",
            ["config/config.yaml"],
            views_of("results"),
            [csv("canonical_centres")],
            [script("canonical_centres", "results", "--out", csv("canonical_centres"))],
        ),
        "docs_open_set": (  # each object left out of the main job's libraries in turn, its test views unknown
            "results",
            ["config/config.yaml"],
            [
                "results/descriptors.parquet",
                *(f"results/libraries/{name}-{size}.parquet" for name in OPEN_SET for size in (40, 8)),
            ],
            [csv("open_set_household"), csv("open_set_household_half")],
            [
                script("open_set", "results", "--size", "40", "8", "--out", csv("open_set_household")),
                script(
                    "open_set",
                    "results",
                    "--size",
                    "40",
                    "8",
                    "--threshold",
                    "0.5",
                    "--out",
                    csv("open_set_household_half"),
                ),
            ],
        ),
        "docs_open_set_chairs": (  # the same on the 58 chairs' library (4 test views a chair)
            "results/chairs_library",
            [f"{E}/chairs.yaml", f"{E}/chairs_library.yaml"],
            [
                "results/chairs_library/descriptors.parquet",
                "results/chairs_library/libraries/hgd_color=hue-saturation-40.parquet",
            ],
            [csv("open_set_chairs"), csv("open_set_chairs_half")],
            [
                script("open_set", "results/chairs_library", "--size", "40", "--out", csv("open_set_chairs")),
                script(
                    "open_set",
                    "results/chairs_library",
                    *("--size", "40", "--threshold", "0.5", "--out", csv("open_set_chairs_half")),
                ),
            ],
        ),
        "docs_learned": (  # the learned kind beside the descriptors on the chairs: 8 and 40 views, unseen objects
            "results/chairs_learned",
            [f"{E}/chairs.yaml", f"{E}/chairs_learned.yaml"],
            [
                "results/chairs_learned/evaluation/precision.csv",
                "results/chairs_learned/descriptors.parquet",
                *views_of("results/chairs_learned"),  # learned_unseen trains and describes from the views
            ],
            [csv("chairs_learned_precision"), csv("chairs_learned_metric"), csv("chairs_learned_unseen")],
            [
                {"precision": ["results/chairs_learned/evaluation/precision.csv", csv("chairs_learned_precision")]},
                script("learned_metric", "results/chairs_learned", "--out", csv("chairs_learned_metric")),
                script(
                    "learned_unseen",
                    "results/chairs_learned",
                    *("--config", f"{E}/chairs.yaml", f"{E}/chairs_learned.yaml"),
                    *("--out", csv("chairs_learned_unseen")),
                ),
            ],
        ),
        "docs_learned_household": (  # the learned kind on the 14 household objects: views, scenes, unseen objects
            "results/household_learned",
            ["config/config.yaml", f"{E}/household_learned.yaml"],
            [
                "results/household_learned/evaluation/precision.csv",
                "results/household_learned/descriptors.parquet",
                "results/household_learned/scenes/summary.csv",
                "results/household_learned/scenes/offaxis.csv",
                *views_of("results/household_learned"),  # learned_unseen trains and describes from the views
                # learned_transfer describes them with the networks trained on the chairs (docs_learned's run)
                *(f"results/chairs_learned/fitted/{name}.npz" for name in ("pointnet", "pointnet_color=none")),
            ],
            [
                csv("household_learned_precision"),
                csv("household_learned_scenes"),
                csv("household_learned_offaxis"),
                csv("household_learned_unseen"),
                csv("household_learned_transfer"),
            ],
            [
                {
                    "precision": [
                        "results/household_learned/evaluation/precision.csv",
                        csv("household_learned_precision"),
                    ]
                },
                {"copy": ["results/household_learned/scenes/summary.csv", csv("household_learned_scenes")]},
                {"copy": ["results/household_learned/scenes/offaxis.csv", csv("household_learned_offaxis")]},
                script(
                    "learned_unseen",
                    "results/household_learned",
                    *("--held-out", "4", "--config", "config/config.yaml", f"{E}/household_learned.yaml"),
                    *("--out", csv("household_learned_unseen")),
                ),
                script(
                    "learned_transfer",
                    "results/household_learned",
                    *("--weights", "results/chairs_learned"),
                    *("--out", csv("household_learned_transfer")),
                ),
            ],
        ),
        "docs_learned_twins": (  # the learned kind on the colour twins, beside the HGD with and without colour
            "results/twins_learned",
            [f"{E}/twins.yaml", f"{E}/twins_learned.yaml"],
            ["results/twins_learned/evaluation/predictions.parquet", "results/twins_learned/catalog.csv"],
            [csv("twins_learned_precision"), png("colour_twins_learned")],
            [
                script(
                    "color_twins",
                    "results/twins_learned",
                    *("--out", csv("twins_learned_precision"), "--figure", png("colour_twins_learned")),
                )
            ],
        ),
        "docs_poses": (  # the default library's poses on the main job's test views, and verification's open set
            "results",
            ["config/config.yaml"],
            [f"results/libraries/{DEFAULT_LIBRARY}", *views_of("results")],
            [csv("poses_household"), csv("open_set_verified_household")],
            [
                script(
                    "poses",
                    "results",
                    *("--library", f"results/libraries/{DEFAULT_LIBRARY}", "--views-per-object", "20"),
                    *("--out", csv("poses_household"), "--open-set-out", csv("open_set_verified_household")),
                )
            ],
        ),
        "docs_poses_chairs": (  # the same on the 58 chairs' library (4 test views a chair)
            "results/chairs_library",
            [f"{E}/chairs.yaml", f"{E}/chairs_library.yaml"],
            [f"results/chairs_library/libraries/{DEFAULT_LIBRARY}", "results/chairs_library/catalog.csv"],
            [
                csv("poses_chairs"),
                csv("open_set_verified_chairs"),
                csv("poses_chairs_whole"),
                csv("open_set_verified_chairs_whole"),
            ],
            [
                script(
                    "poses",
                    "results/chairs_library",
                    *("--library", f"results/chairs_library/libraries/{DEFAULT_LIBRARY}", "--views-per-object", "4"),
                    *("--out", csv("poses_chairs"), "--open-set-out", csv("open_set_verified_chairs")),
                ),
                script(  # the same views with every piece kept, as a scene's segment keeps them
                    "poses",
                    "results/chairs_library",
                    *("--library", f"results/chairs_library/libraries/{DEFAULT_LIBRARY}", "--views-per-object", "4"),
                    *("--whole", "--out", csv("poses_chairs_whole")),
                    *("--open-set-out", csv("open_set_verified_chairs_whole")),
                ),
            ],
        ),
        "docs_kinect": (
            "results/kinect",
            [f"{E}/kinect.yaml"],
            ["results/evaluation/precision.csv", "results/kinect/evaluation/precision.csv"],
            [csv("household_sensor")],
            [
                {"precision": ["results/evaluation/precision.csv", "results/kinect/published/noise.csv"]},
                {"precision": ["results/kinect/evaluation/precision.csv", "results/kinect/published/kinect.csv"]},
                {
                    "labelled": [
                        "sensor",
                        {
                            "noise (2.6.1)": "results/kinect/published/noise.csv",
                            "kinect": "results/kinect/published/kinect.csv",
                        },
                        csv("household_sensor"),
                    ]
                },
            ],
        ),
        "docs_scenes": (
            "results/scenes_run",
            [f"{E}/scenes.yaml"],
            [
                "results/scenes_run/catalog.csv",  # the ablation renders the scenes' objects again
                "results/scenes_run/scenes/summary.csv",
                "results/scenes_run/scenes/offaxis.csv",
                "results/scenes_run/scenes/overlays/scene-061.png",
                "results/scenes_run/scenes/overlays/scene-093.png",
            ],
            [
                csv("scenes_summary"),
                csv("scenes_offaxis"),
                csv("scenes_ablation"),
                png("scene_overlay_61"),
                png("scene_overlay_93"),
            ],
            [
                {"copy": ["results/scenes_run/scenes/summary.csv", csv("scenes_summary")]},
                {"copy": ["results/scenes_run/scenes/offaxis.csv", csv("scenes_offaxis")]},
                {"copy": ["results/scenes_run/scenes/overlays/scene-061.png", png("scene_overlay_61")]},
                {"copy": ["results/scenes_run/scenes/overlays/scene-093.png", png("scene_overlay_93")]},
                script("scene_ablation", "results/scenes_run", "--scenes", "30", "--out", csv("scenes_ablation")),
            ],
        ),
        "docs_library_growth": (  # precision against the number of objects, 200 Sweet Home 3D models
            "results/furniture",
            [f"{E}/furniture.yaml"],
            ["results/furniture/descriptors.parquet"],
            [csv("library_growth"), png("library_growth")],
            [
                script(
                    "library_growth",
                    "results/furniture",
                    *("--objects", "14", "58", "200", "--draws", "5"),
                    *("--out", csv("library_growth"), "--figure", png("library_growth")),
                )
            ],
        ),
        "docs_complex_steps": (  # draws the two published step tables (docs_chairs_12's and docs_main's)
            None,
            [],
            [],
            [png("complex_steps")],
            [
                script(
                    "complex_ablation",
                    "--plot",
                    csv("chairs_12_steps"),
                    csv("household_steps"),
                    "--figure",
                    png("complex_steps"),
                )
            ],
        ),
    }
    return {name: Target(*entry) for name, entry in table.items()}

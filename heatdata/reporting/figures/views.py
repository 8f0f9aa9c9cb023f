"""Views coloured by temperature or global derivative; a catalogue's example views (thesis Fig. 2.3/2.4, 5.7)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from heatdata.errors import HeatdataError
from heatdata.io.files import atomic
from heatdata.reporting.figures.common import RENDERED_NOTE

TEMPERATURE_LABEL = "temperature (equilibrium = 1)"


DERIVATIVE_LABEL = "global derivative (eq. 5.12), 1/m^2"


DERIVATIVE_HEADING = (
    "Source-position global derivative (eq. 5.12) at t_global = 1/lambda_2: large where a source "
    "would heat a loosely connected part (Fig. 5.7); star: the source"
)


def plot_views(
    views: list,
    values: list,
    sources: list,
    path: str | Path,
    titles: list[str],
    *,
    heading: str,
    colorbar_label: str = TEMPERATURE_LABEL,
    cmap: str = "inferno",
) -> None:
    """Partial views coloured by per-vertex ``values`` (e.g. temperature at t_s), source and boundary marked."""
    if not views:
        raise HeatdataError("no views to draw")
    cols = min(4, len(views))
    rows = int(np.ceil(len(views) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.2 * rows), squeeze=False)
    for ax, view, value, source, title in zip(axes.ravel(), views, values, sources, titles, strict=False):
        p = view.pixels
        collection = ax.tripcolor(p[:, 0], p[:, 1], view.faces, value, shading="gouraud", cmap=cmap)
        b = np.append(view.boundary, view.boundary[0])
        ax.plot(p[b, 0], p[b, 1], color="cyan", lw=0.8)
        ax.plot(*p[view.boundary[0]], "o", color="cyan", ms=4)
        ax.plot(*p[source], "*", color="lime", ms=12, mec="black")
        ax.set_aspect("equal")
        ax.invert_yaxis()
        ax.set_axis_off()
        ax.set_title(title, fontsize=8)
        fig.colorbar(collection, ax=ax, fraction=0.04, pad=0.02).set_label(colorbar_label, fontsize=7)
    for ax in axes.ravel()[len(views) :]:
        ax.set_axis_off()
    fig.suptitle(f"{heading}\n{RENDERED_NOTE}", fontsize=8)
    fig.tight_layout()
    with atomic(path) as temporary:
        fig.savefig(temporary, dpi=110)
    plt.close(fig)


def draw_example_views(
    catalog: pd.DataFrame,
    path: str | Path,
    *,
    elevation: float = 30.0,
    distance: float | str = 1.0,
    noise: bool = True,
    seed: int = 0,
    count: int = 8,
    image_scale: float = 1.0,
    source: str = "closest",
    derivative_path: str | Path | None = None,
) -> None:
    """Render up to ``count`` catalogue objects at azimuth 30 deg and draw the temperature of a PVHK.

    ``distance``: metres, or ``"fit"`` (:func:`heatdata.views.render.camera_distance`).
    ``source`` is the PVHK's source rule (the report passes its primary descriptor's). With
    ``derivative_path``, also draw the global derivative of the same views (Fig. 5.7) on the
    component holding the source.
    """
    from heatdata.descriptors import global_derivative, heat_kernel, pvhk
    from heatdata.io.catalog import load_catalog_model
    from heatdata.views.render import camera_distance, render_view
    from heatdata.views.view import kinect_intrinsics

    intrinsics = kinect_intrinsics(image_scale)
    views, temps, sources, titles, components, derivatives, local_sources = [], [], [], [], [], [], []
    for _, row in catalog.head(count).iterrows():
        model = load_catalog_model(row)
        view = render_view(
            model,
            30.0,
            elevation,
            camera_distance(model, distance, intrinsics),
            noise=noise,
            seed=seed,
            intrinsics=intrinsics,
        )
        d = pvhk(view, 64, source)
        views.append(view)
        temps.append(heat_kernel(view, d.source, [d.time])[0])
        sources.append(d.source)
        titles.append(f"{row['object']} ({view.n_vertices} vertices)")
        if derivative_path is not None:
            component, local = view.component_of(d.source)
            components.append(component)
            local_sources.append(local)
            derivatives.append(global_derivative(component, local))
    plot_views(
        views,
        temps,
        sources,
        path,
        titles,
        heading=f"Temperature at t_s = 1/lambda_2 after a pulse at the {source!r} source (star); dot: boundary origin",
    )
    if derivative_path is not None:
        plot_views(
            components,
            derivatives,
            local_sources,
            derivative_path,
            titles,
            heading=DERIVATIVE_HEADING,
            colorbar_label=DERIVATIVE_LABEL,
            cmap="viridis",
        )

"""Interactive figures (plotly) for a page: lines and markers on one pair of axes,
zoomable, with each point's values on hover. plotly is imported on first use; where it
is not installed, `available()` is False and a page shows its static PNGs instead.

- `lines_figure(traces, x_label, y_label, title, log_x, log_y)`: a plotly `Figure` of
  `traces`, each a `Trace` (a name, the x and y values, and how it is drawn).
- `figure_html(fig, div_id)`: the figure as an HTML fragment without plotly.js;
  `plotly_js()`: plotly.js itself, to put once in the page (no network needed)."""

from typing import NamedTuple

import numpy as np


class Trace(NamedTuple):
    """One curve or set of markers: `mode` "lines", "markers" or "lines+markers";
    `dash` "solid", "dash" or "dot"; `colour` a CSS colour or None (plotly's cycle);
    `values` (optional) a number per point, shown on hover and as the markers'
    colour (`values_label` names it; one colour scale for all the traces);
    `labels` (optional) a word per point, shown on hover."""

    name: str
    x: object
    y: object
    mode: str = "lines"
    dash: str = "solid"
    colour: str | None = None
    values: object = None
    values_label: str = ""
    labels: object = None


def available() -> bool:
    """Whether plotly can be imported."""
    try:
        import plotly  # noqa: F401
    except ImportError:
        return False
    return True


def _finite(a):
    """`a` as a list of floats with None where it is not finite (gaps in a line)."""
    a = np.asarray(a, dtype=float)
    return [float(v) if np.isfinite(v) else None for v in a.ravel()]


def lines_figure(traces, x_label, y_label, title="", log_x=False, log_y=False):
    """A plotly `Figure` of `traces` (`Trace`s) on one pair of axes."""
    import plotly.graph_objects as go

    fig = go.Figure()
    coloured = [v for t in traces if t.values is not None for v in _finite(t.values) if v is not None]
    scale = (min(coloured), max(coloured)) if coloured else (0.0, 1.0)
    first = True
    for t in traces:
        marker = {} if t.colour is None else {"color": t.colour}
        extra = {}
        if t.values is not None:
            marker = {"color": _finite(t.values), "colorscale": "Viridis", "cmin": scale[0],
                      "cmax": scale[1] if scale[1] > scale[0] else scale[0] + 1e-12, "showscale": first,
                      "colorbar": {"title": t.values_label}}
            first = False
            extra = {"customdata": _finite(t.values),
                     "hovertemplate": f"x=%{{x:.6g}}<br>y=%{{y:.6g}}<br>{t.values_label}=%{{customdata:.4g}}"}
        if t.labels is not None:
            extra["text"] = [str(v) for v in np.ravel(t.labels)]
            extra["hovertemplate"] = extra.get("hovertemplate", "x=%{x:.6g}<br>y=%{y:.6g}") + "<br>%{text}"
        fig.add_trace(go.Scatter(x=_finite(t.x), y=_finite(t.y), name=t.name, mode=t.mode, marker=marker,
                                 line={"dash": t.dash, **({} if t.colour is None else {"color": t.colour})},
                                 connectgaps=False, **extra))
    fig.update_layout(title=title, template="plotly_white", height=480, margin={"l": 70, "r": 30, "t": 60, "b": 60},
                      legend={"orientation": "h", "y": -0.2})
    fig.update_xaxes(title_text=x_label, type="log" if log_x else "linear")
    fig.update_yaxes(title_text=y_label, type="log" if log_y else "linear")
    return fig


def figure_html(fig, div_id):
    """`fig` as an HTML fragment (a div and its script), plotly.js not included."""
    import plotly.io as pio

    return pio.to_html(fig, full_html=False, include_plotlyjs=False, div_id=div_id,
                       config={"displaylogo": False, "responsive": True})


def plotly_js():
    """plotly.js, to inline once in a page that holds `figure_html` fragments."""
    from plotly.offline import get_plotlyjs

    return get_plotlyjs()

"""One self-contained HTML report of a scan: a sortable table and a figure per loop.

Everything is inside the one file (figures as base64 PNG, the sorting script inline), so
it can be mailed, archived or opened offline; nothing is fetched from the network.
"""

from __future__ import annotations

import base64
import html
import io
from pathlib import Path

import numpy as np
import pandas as pd

from .._validation import check_loops

# (report column, header, how to show it)
TABLE_COLUMNS = (
    ("file", "file", "text"),
    ("tag", "tag", "text"),
    ("cause", "known cause", "text"),
    ("verdict", "verdict", "text"),
    ("stiction_probability", "p(stiction)", "prob"),
    ("stiction_size_mean", "stiction size, % travel", "num1"),
    ("stiction_band_fit", "fitted dead band, % travel", "num1"),
    ("oscillating", "oscillates", "text"),
    ("period", "period", "num1"),
    ("area_ratio", "area ratio", "num2"),
    ("status", "status", "text"),
    ("reason", "reason", "text"),
)

_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:1.5em;color:#222}
h1{font-size:1.4em;margin-bottom:.2em} h2{font-size:1.1em;margin:1.6em 0 .3em}
.summary{color:#555;margin-bottom:1em}
table{border-collapse:collapse;font-size:.86em}
th,td{padding:.25em .6em;border-bottom:1px solid #ddd;text-align:left;vertical-align:top}
th{background:#f3f4f6;cursor:pointer;user-select:none;position:sticky;top:0}
th.sorted-asc::after{content:" \\25B2"} th.sorted-desc::after{content:" \\25BC"}
td.num{text-align:right;font-variant-numeric:tabular-nums}
td.file{max-width:26em;overflow-wrap:anywhere} td.reason{max-width:24em}
tr.stiction td.verdict{color:#b91c1c;font-weight:600}
tr.no_stiction td.verdict{color:#15803d}
tr.no_verdict td.verdict{color:#6b7280}
.loop{border-top:1px solid #ccc;margin-top:1.2em}
.loop img{max-width:100%;height:auto}
.note{color:#6b7280;font-style:italic}
"""

# Sort on click; numbers by their data-value. It also marks the page ready for tests.
_JS = r"""
(function(){
  var table=document.getElementById('loops');
  var heads=table.tHead.rows[0].cells;
  function key(td){var v=td.getAttribute('data-value');
    if(v!==null&&v!==''){return parseFloat(v);} return td.textContent.toLowerCase();}
  function sortBy(col){
    var body=table.tBodies[0]; var rows=Array.prototype.slice.call(body.rows);
    var th=heads[col]; var asc=!th.classList.contains('sorted-asc');
    for(var i=0;i<heads.length;i++){heads[i].classList.remove('sorted-asc','sorted-desc');}
    th.classList.add(asc?'sorted-asc':'sorted-desc');
    rows.sort(function(a,b){var x=key(a.cells[col]),y=key(b.cells[col]);
      var nx=(typeof x==='number'&&!isNaN(x)),ny=(typeof y==='number'&&!isNaN(y));
      if(nx!==ny){return nx?-1:1;}
      if(x<y){return asc?-1:1;} if(x>y){return asc?1:-1;} return 0;});
    rows.forEach(function(r){body.appendChild(r);});
  }
  for(var i=0;i<heads.length;i++){(function(c){heads[c].addEventListener('click',
    function(){sortBy(c);});})(i);}
  // #sort=NAME opens the table sorted by the report column NAME (#sort=-NAME: descending);
  // names survive columns being added, unlike the older #sort=N (N counts from 0)
  var m=/^#sort=(-?)([A-Za-z0-9_]+)$/.exec(window.location.hash), col=-1;
  if(m){for(var j=0;j<heads.length;j++){if(heads[j].getAttribute('data-col')===m[2]){col=j;}}
    if(col<0&&/^\d+$/.test(m[2])&&+m[2]<heads.length){col=+m[2];}}
  if(col>=0){sortBy(col);if(m[1]==='-'){sortBy(col);}}
  function check(){
    var pics=document.images, ok=0;
    for(var i=0;i<pics.length;i++){if(pics[i].complete&&pics[i].naturalWidth>0){ok++;}}
    document.body.setAttribute('data-images-ok',String(ok));
    document.body.setAttribute('data-rows',String(table.tBodies[0].rows.length));
    document.body.setAttribute('data-ready','1');
  }
  if(document.readyState==='complete'){check();}else{window.addEventListener('load',check);}
})();
"""


def _fmt(value, kind):
    """(text shown, data-value for sorting) of one cell."""
    if kind == "text":
        text = "" if value is None or (isinstance(value, float) and np.isnan(value)) else value
        return html.escape(str(text)), ""
    try:
        x = float(value)
    except (TypeError, ValueError):
        return html.escape(str(value)), ""
    if not np.isfinite(x):
        return "", ""
    return _decimals(x, {"prob": 2, "num1": 1, "num2": 2}[kind]), repr(x)


def _decimals(x, digits):
    """``x`` as text to ``digits`` decimals; a small negative number shows ``0.00``, not
    the ``-0.00`` it rounds to (the console's table shows numbers this way too)."""
    text = f"{x:.{digits}f}"
    return text.lstrip("-") if float(text) == 0 else text


def _valve_summary(report):
    """A sentence on the valves when some valve (tag) has several records, else ""."""
    if "tag" not in report or "verdict" not in report:
        return ""
    from .valves import several_records, summarise_valves

    valves = summarise_valves(report)
    if not several_records(valves):
        return ""
    sticky = valves[valves["verdict"].eq("stiction")]
    named = ", ".join(f"{t} ({int(k)} of {int(j)})" for t, k, j in
                      zip(sticky["tag"], sticky["n_stiction"], sticky["n_judged"]))  # fmt: skip
    noun = "valve" if len(valves) == 1 else "valves"
    return (f". {len(valves)} {noun}; called sticky in at least half of their judged "
            f"records: {len(sticky)}" + (f", {named}" if named else ""))


def _figure_png(fig, dpi):
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def _label(report, i):
    for col in ("tag", "file"):
        if col in report and isinstance(report[col].iloc[i], str) and report[col].iloc[i]:
            return report[col].iloc[i]
    return f"loop {i}"


def _figure_title(report, i):
    """The loop's name, then its verdict with the probability and sizes a scan gave."""
    parts = [_label(report, i)]
    row = report.iloc[i]
    if isinstance(row.get("verdict"), str):
        verdict = row["verdict"].replace("_", " ")
        p = row.get("stiction_probability", np.nan)
        parts.append(f"{verdict} (p = {p:.2f})" if np.isfinite(p) else verdict)
    for col, name in (("stiction_size_mean", "peak-to-peak"),
                      ("stiction_band_fit", "fitted band")):  # fmt: skip
        value = row.get(col, np.nan)
        if np.isfinite(value):
            parts.append(f"{name} {_decimals(value, 2)} %")
    return ", ".join(parts)


def _loop_getter(X, n):
    """``i -> loop i as (1, n_samples, 3)`` (or None) from an array or a callable."""
    if X is None:
        return None
    if callable(X):
        return lambda i: None if (one := X(i)) is None else check_loops(np.asarray(one)[None])
    loops = check_loops(X)
    if len(loops) != n:
        raise ValueError(f"X has {len(loops)} loops but the report has {n} rows; "
                         "they must match.")
    return lambda i: loops[i : i + 1]


def _render(loops, ts, titles, dpi):
    """(base64 PNG or "error: ..." or None, median cycle period) for each loop given."""
    import matplotlib
    import matplotlib.style

    from .plots import loop_cycles, plot_loop_summary

    out = []
    # matplotlib's defaults, not the caller's style: a worker process draws the same
    with matplotlib.style.context("default"), matplotlib.rc_context({"font.size": 8}):
        for one, step, title in zip(loops, ts, titles):
            if isinstance(one, str):  # the loop could not be read
                out.append((one, np.nan))
                continue
            if one is None or np.isnan(one[0, :, 0]).all():
                out.append((None, np.nan))
                continue
            try:
                cycles = loop_cycles(one)
                period = np.nan
                if len(cycles) and "period" in cycles:
                    period = float(np.median(cycles["period"])) * step
                fig = plot_loop_summary(one, ts=step, cycles=cycles, title=title)
                out.append((_figure_png(fig, dpi), period))
            except Exception as exc:  # noqa: BLE001 - a figure must not stop the report
                out.append((f"error: {type(exc).__name__}: {exc}", np.nan))
    return out


def _read(loop_of, i):
    try:
        return loop_of(i)
    except Exception as exc:  # noqa: BLE001 - a figure must not stop the report
        return f"error: {type(exc).__name__}: {exc}"


def _figures(report, loop_of, order, ts, dpi, n_jobs, progress, chunk=8, batch=4):
    """Figures of the loops ``order``, drawn in chunks on ``n_jobs`` processes; loops
    are read here, in order (a file read once), ``batch`` chunks at a time, so memory
    holds a few chunks' loops, not every figure's."""
    from .scan import progress_bar, run_units

    order = sorted(order)
    chunks = [order[a : a + chunk] for a in range(0, len(order), chunk)]
    drawn = []
    with progress_bar(len(order), progress, unit="figure", desc="figures") as bar:
        for b in range(0, len(chunks), batch):
            units = [([_read(loop_of, i) for i in part], ts[part],
                      [_figure_title(report, i) for i in part], dpi)
                     for part in chunks[b : b + batch]]  # fmt: skip
            done = run_units(_render, units, (), n_jobs=n_jobs, bar=bar,
                             sizes=[len(u[0]) for u in units])
            drawn.extend(d for part in done for d in part)
    return dict(zip(order, drawn))


def write_html_report(report, X=None, path="sktiction_report.html", *, ts=None,
                      title="sktiction report", max_figures=200, dpi=72, n_jobs=None,
                      progress=False):
    """Write a scan report as ONE self-contained HTML file people would rather read.

    A sortable table of loops (click a header to sort, or open the file with
    ``#sort=NAME`` to sort by the report column ``NAME``, ``#sort=-NAME`` for
    descending, e.g. ``#sort=-stiction_probability``: verdict, probability of
    stiction, stiction size in % of valve travel, the fitted dead band, whether the loop
    oscillates and its period (a scan's ``oscillation_period`` times the sample time, else
    the drawn cycles'), area ratio, status and reason), then for each loop a figure: the
    trend of PV, SP and OP
    with the detected cycles shaded and the matched OP/PV templates named on each
    cycle, PV against OP, and the area ratio R of each cycle. Figures are base64
    PNG and the sorting script is inline: the file needs no network.

    Parameters
    ----------
    report : pandas.DataFrame
        One row per loop, e.g. from :func:`~sktiction.reports.scan_loops`; columns
        it lacks are left out of the table (``file`` and ``tag`` name the rows).
    X : array-like of shape (n_loops, n_samples, n_channels), callable or None, default=None
        The loops of the report, in its order, for the figures; or a function
        ``X(i)`` returning loop ``i`` as ``(n_samples, 3)`` (or None), so that a
        streamed scan can read its files again one at a time; ``None`` writes the
        table only.
    path : str or Path, default="sktiction_report.html"
        Where to write.
    ts : float, array-like of shape (n_loops,) or None, default=None
        Sampling time of each loop for the time axes; ``None`` takes the report's
        ``ts`` (or ``input_ts``) column, else 1.
    title : str, default="sktiction report"
        Page title.
    max_figures : int, default=200
        Figures for at most this many loops (sticky verdicts first), so the file
        stays small for plant-wide scans; the table always lists every loop.
    dpi : int, default=72
        Resolution of the figures.
    n_jobs : int or None, default=None
        Processes drawing the figures (joblib's convention: ``-1`` all cores).
    progress : bool, default=False
        Show a progress bar over the figures with rate and ETA on standard error.

    Returns
    -------
    path : Path
        The file written.

    Examples
    --------
    >>> import tempfile, matplotlib
    >>> matplotlib.use("Agg")
    >>> import pandas as pd
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.reports.html import write_html_report
    >>> X, _ = make_loops(2, n_samples=600, random_state=0)
    >>> report = pd.DataFrame({"tag": ["FIC1", "FIC2"], "verdict": ["stiction", "no_stiction"]})
    >>> out = write_html_report(report, X, path=tempfile.mktemp(suffix=".html"))
    >>> text = out.read_text()
    >>> text.count("<img"), "FIC2" in text
    (2, True)
    """

    report = report.reset_index(drop=True)
    if "tag" in report:  # a tag column of numbers read as floats: 101, not 101.0
        from .valves import _whole

        report = report.assign(tag=report["tag"].astype(object).map(_whole))
    n = len(report)
    loop_of = _loop_getter(X, n)
    if ts is None:
        for col in ("ts", "input_ts"):
            if col in report:
                ts = report[col].to_numpy(dtype=float)
                break
    ts = np.broadcast_to(np.asarray(1.0 if ts is None else ts, dtype=float), (n,))
    ts = np.where(np.isfinite(ts) & (ts > 0), ts, 1.0)

    # Figures first: their cycle tables also give each loop's period when the report has none.
    figures = {}
    periods = np.full(n, np.nan)
    if loop_of is not None:
        verdict = report["verdict"] if "verdict" in report else pd.Series("", index=report.index)
        order = np.argsort(~verdict.eq("stiction").to_numpy(), kind="stable")[:max_figures]
        drawn = _figures(report, loop_of, order, ts, dpi, n_jobs, progress)
        for i, (png, period) in drawn.items():
            figures[i], periods[i] = png, period
    table = report.copy()
    if "period" not in table:
        if "oscillation_period" in table:  # a scan's: every loop, drawn or not
            scanned = table["oscillation_period"].to_numpy(dtype=float) * ts
            periods = np.where(np.isfinite(scanned), scanned, periods)
        table["period"] = periods
    if "oscillating" in table:
        table["oscillating"] = ["" if pd.isna(v) else "yes" if v else "no"
                                for v in table["oscillating"].astype(object)]  # fmt: skip
    if "status" not in table and "input_status" in table:
        table["status"] = table["input_status"]

    cols = [c for c in TABLE_COLUMNS if c[0] in table]
    head = "".join(f'<th data-col="{c}">{html.escape(h)}</th>' for c, h, _ in cols)
    body = []
    for i in range(n):
        verdict = str(table["verdict"].iloc[i]) if "verdict" in table else ""
        cells = []
        for col, _, kind in cols:
            shown, value = _fmt(table[col].iloc[i], kind)
            if col in ("file", "tag") and i in figures:
                shown = f'<a href="#loop-{i}">{shown}</a>'
            cls = f' class="{col}"' if kind == "text" else ' class="num"'
            val = f' data-value="{value}"' if value else ""
            cells.append(f"<td{cls}{val}>{shown}</td>")
        body.append(f'<tr class="{html.escape(verdict)}" id="row-{i}">{"".join(cells)}</tr>')

    counts = table["verdict"].value_counts() if "verdict" in table else pd.Series(dtype=int)
    summary = ", ".join(f"{v}: {int(c)}" for v, c in counts.items())
    # a sentence only when there is something to say (no verdicts: no empty ". ")
    summary = (summary + _valve_summary(report)).removeprefix(". ")
    summary = f"{html.escape(summary)}. " if summary else ""
    sections = []
    for i, png in figures.items():
        name = html.escape(_label(report, i))
        verdict = html.escape(str(table["verdict"].iloc[i])) if "verdict" in table else ""
        reason = html.escape(str(table["reason"].iloc[i])) if "reason" in table else ""
        if png is None or png.startswith("error:"):
            inner = f'<p class="note">no figure: {html.escape(png or "no data")}</p>'
        else:
            inner = (f'<img alt="PV, SP and OP of {name} with its cycles, PV against OP and '
                     f'R per cycle" src="data:image/png;base64,{png}">')
        sections.append(
            f'<section class="loop" id="loop-{i}"><h2>{name}: {verdict}</h2>'
            f'<p class="summary">{reason}</p>{inner}</section>'
        )
    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{html.escape(title)}</title><style>{_CSS}</style></head>
<body>
<h1>{html.escape(title)}</h1>
<p class="summary">{n} loops. {summary}Click a column header to sort; click a
file or tag to see its figure: PV, SP and OP with the analysed cycles shaded and the OP/PV
template that matches each cycle best (e.g. <i>tria/rect</i>: OP triangular, PV rectangular),
PV against OP, and the area ratio R of each cycle.</p>
<table id="loops"><thead><tr>{head}</tr></thead><tbody>
{"".join(body)}
</tbody></table>
{"".join(sections)}
<script>{_JS}</script>
</body></html>
"""
    path = Path(path)
    path.write_text(page, encoding="utf-8")
    return path

"""Issue 35 item 4 (the page without its interactive figures, on a branch): `rotorjax
report` writes one self-contained HTML page of the everyday analyses. Checked: every
section is there with its figures embedded and nothing fetched from outside; the
API 684 table against an independent computation (numpy's eigenvalues of the state
matrix at each critical speed for the amplification factor, API 684's formula for
the required margin); the tables' numbers are the commands' own; a section whose
analysis fails says so on the page and the command exits 3."""

import html.parser
import json
import math

import numpy as np
import pytest

from rotorjax.cli import main
from rotorjax.cli._report import SECTIONS
from rotorjax.io import read_rotor_file

SETS = ["--set", "bearing0.cxx=500", "--set", "bearing1.cxx=500"]
OPERATING = (300.0, 400.0)


class _Page(html.parser.HTMLParser):
    """Sections (by id), their images and their tables' cells."""

    def __init__(self):
        super().__init__()
        self.sections, self.current, self.cell, self.external = {}, None, None, []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "section":
            self.current = self.sections.setdefault(a["id"], {"images": 0, "cells": [], "text": ""})
        if tag == "img" and self.current is not None:
            self.current["images"] += 1
            assert a["src"].startswith("data:image/png;base64,")
        for key in ("src", "href"):
            if key in a and not (a[key].startswith("data:") or a[key].startswith("#")):
                self.external.append(a[key])
        if tag == "td":
            self.cell = ""

    def handle_endtag(self, tag):
        if tag == "td" and self.current is not None:
            self.current["cells"].append(self.cell)
            self.cell = None
        if tag == "section":
            self.current = None

    def handle_data(self, data):
        if self.cell is not None:
            self.cell += data
        if self.current is not None:
            self.current["text"] += data


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    argv = ["report", "ross_compare.toml", *SETS, "--operating", *map(str, OPERATING), "--out", str(out), "--json"]
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(argv) == 0
    summary = json.loads(buf.getvalue())
    page = _Page()
    page.feed(open(summary["report"], encoding="utf-8").read())
    return summary, page, out


def test_every_section_is_there_with_its_figures_and_nothing_from_outside(report):
    summary, page, _ = report
    assert list(page.sections) == [c for c, _ in SECTIONS] == summary["sections"]
    for command, section in page.sections.items():
        assert section["images"] >= 1, command
        assert section["cells"], command
    assert page.external == [] and summary["failed"] == {}


def test_the_api684_table_against_an_independent_computation(report):
    """Each critical speed's amplification factor `|lambda| / (-2 Re lambda)` from
    numpy's eigenvalues of the state matrix assembled at that speed (the eigenvalue
    whose imaginary part is the speed), and the margins from API 684's formula."""
    summary, _, _ = report
    rows = summary["api684"]
    assert len(rows) == 2
    scene = read_rotor_file("ross_compare.toml", {"bearing0.cxx": 500.0, "bearing1.cxx": 500.0}).scene
    lo, hi = OPERATING
    for r in rows:
        lm = scene.linear_matrices(r["speed"])
        M, C, K = (np.asarray(a) for a in (lm.M, lm.C + lm.G, lm.K))
        n = M.shape[0]
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
        lam = np.linalg.eigvals(A)
        lam = lam[np.argmin(np.abs(lam.imag - r["speed"]))]
        assert abs(lam.imag - r["speed"]) < 1e-6 * r["speed"]
        af = abs(lam) / (-2 * lam.real)
        assert r["af"] == pytest.approx(af, rel=1e-9)
        below = r["speed"] <= 0.5 * (lo + hi)
        have = 100 * (lo - r["speed"]) / lo if below else 100 * (r["speed"] - hi) / hi
        base = 17 * (1 - 1 / max(af - 1.5, 1.0))
        need = 0.0 if af < 2.5 else (min(16.0, base) if below else min(26.0, 10 + base))
        assert r["margin"] == pytest.approx(have, rel=1e-12) and r["required"] == pytest.approx(need, rel=1e-12)
        assert r["meets"] == (have >= need)
    assert [r["meets"] for r in rows] == [True, False]     # 96 rad/s clears 300..400; 300.8 rad/s is inside it


def test_the_tables_are_the_commands_numbers(report, tmp_path, capsys):
    """The modes table is `rotorjax modes --speed 400` (the operating range's top), the
    static table `static`'s JSON; the bearings carry the weight; the mass is 88.18 kg."""
    _, page, out = report
    assert main(["modes", "ross_compare.toml", *SETS, "--speed", "400", "--json", "--out", str(tmp_path)]) == 0
    modes = json.loads(capsys.readouterr().out)["modes"]
    cells = page.sections["modes"]["cells"]
    assert cells == [x for m in modes for x in (str(m["mode"]), f"{m['damped_frequency']:.6g}", f"{m['log_dec']:.6g}",
                                                 f"{m['damping_ratio']:.6g}", m["whirl"])]
    static = json.load(open(next((out / "report_parts").glob("static_*.json"))))
    reactions = page.sections["static"]["cells"]
    r0 = static["bearing_reactions"][0]
    assert reactions[:4] == [str(r0["bearing"]), str(r0["node"]), f"{r0['x']:.6g}", f"{r0['y']:.6g}"]
    # the two bearings carry the weight
    weight = static["weight"][1]
    assert sum(r["y"] for r in static["bearing_reactions"]) == pytest.approx(-weight, rel=1e-9)
    assert math.isclose(float(page.sections["draw"]["cells"][1]), 88.1818, rel_tol=1e-5)


def test_a_section_that_fails_is_said_on_the_page_and_exits_3(tmp_path, capsys):
    """The undamped rotor has no level I threshold (its log decrement at Q = 0 is 0)."""
    rc = main(["report", "ross_compare.toml", "--operating", "300", "400", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert rc == 3 and "report section level1 not computed: level1: no threshold Q0 found" in err
    page = _Page()
    page.feed(next(tmp_path.glob("report_*.html")).read_text())
    assert "Not computed: level1: no threshold Q0 found" in page.sections["level1"]["text"]
    assert page.sections["campbell"]["images"] >= 1


def test_the_tables_are_in_the_units_each_command_states():
    """`--units`: each section's table heads name the units of its command's JSON, and
    the API 684 table (computed in SI) is shown in the section's speed unit."""
    from rotorjax.cli._report import page

    rpm = 30 / math.pi
    modes = {"units": {"system": "rpm-um", "speed": "rpm", "frequency": "cpm"}, "files": {},
             "modes": [{"mode": 0, "damped_frequency": 1200.0, "log_dec": 0.1, "damping_ratio": 0.02,
                        "whirl": "forward"}]}
    crit = {"units": {"system": "rpm-um", "speed": "rpm"}, "files": {},
            "api684": {"rows": [{"speed": 100.0, "mode": 1, "af": 3.0, "margin": 20.0, "required": 10.0,
                                 "meets": True}]}}
    text = page("t", {"modes": modes, "critical-speeds": crit})
    assert "<th>damped frequency (cpm)</th>" in text and "<td>1200</td>" in text
    assert "<th>critical speed (rpm)</th>" in text and f"<td>{100 * rpm:.6g}</td>" in text
    assert "<th>damped frequency (rad/s)</th>" in page("t", {"modes": dict(modes, units={})})


def _chromium():
    """The system's Chromium (Debian's package; .ci/run installs it), or None."""
    import shutil

    return next((p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None)


#: the sections with an interactive figure (plotly), the others show their PNGs
INTERACTIVE = ("static", "ucs", "campbell", "response", "level1")


def test_the_page_opens_in_a_headless_browser_without_script_errors(report, tmp_path):
    """Issue 35 item 4: the page in a real browser (headless Chromium, driven by
    playwright): it loads with no script error or console error, every section is
    there, every interactive figure is drawn by plotly.js (inlined: the page fetches
    nothing), and a screenshot is taken."""
    chromium = _chromium()
    if chromium is None:
        pytest.skip("no Chromium on this machine (.ci/run installs Debian's chromium package)")
    sync_playwright = pytest.importorskip("playwright.sync_api", reason="playwright: the test extra").sync_playwright
    summary, _, _ = report
    errors, requests = [], []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=["--no-sandbox", "--disable-gpu"])
        try:
            view = browser.new_page(viewport={"width": 1200, "height": 900})
            view.on("pageerror", lambda e: errors.append(f"page error: {e}"))
            view.on("console", lambda m: errors.append(f"console {m.type}: {m.text}") if m.type == "error" else None)
            view.on("request", lambda r: requests.append(r.url))
            view.goto(f"file://{summary['report']}")
            view.wait_for_load_state("load")
            sections = view.evaluate("[...document.querySelectorAll('section')].map(s => s.id)")
            drawn = view.evaluate("[...document.querySelectorAll('.js-plotly-plot')]"
                                  ".filter(d => d.querySelector('.main-svg')).map(d => d.id)")
            shot = tmp_path / "report.png"
            view.screenshot(path=str(shot), full_page=True)
        finally:
            browser.close()
    assert errors == []
    assert sections == [c for c, _ in SECTIONS]
    assert sorted(drawn) == sorted(f"figure-{c}" for c in INTERACTIVE)
    assert [u for u in requests if not u.startswith(("file:", "data:"))] == []
    data = shot.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 50_000


def test_without_plotly_the_page_shows_its_static_figures(report):
    """The fallback: no script in the page, every section's PNGs shown."""
    from rotorjax.cli._report import _pngs, page

    out = {"files": {"plot": None}, "intersections": [], "critical_speeds": [[1.0]], "stiffness": [1.0],
           "bearing_speeds": [1.0], "bearing_kxx": [[1.0]], "bearing_kyy": [[1.0]]}
    text = page("t", {"ucs": out}, interactive=False)
    assert "<script" not in text and 'id="ucs"' in text
    assert _pngs({"plot": None}) == []
    _, parsed, _ = report
    assert parsed.sections["campbell"]["images"] >= 1     # the interactive page keeps them, in <noscript>

"""The 3-D replay (``tetherheli view``, ``tetherheli.viz.replay``): one self-contained HTML
file of strict JSON data and the inlined three.js, checked in headless Chromium when one is
installed (the test says why it skips otherwise)."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from tests.test_animation import write_run
from tetherheli.cli import main
from tetherheli.viz.replay import replay_data, write_replay
from tetherheli.viz.run_data import RunData, load_run

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable", "chrome")
#: Headless, offline and without GPU: WebGL through ANGLE's SwiftShader (software), which
#: Chromium 137+ enables only on request.
BROWSER_FLAGS = (
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--no-first-run", "--hide-scrollbars",
    "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--window-size=800,560",
    "--virtual-time-budget=8000",
)  # fmt: skip


@pytest.fixture
def results(tmp_path: Path) -> Path:
    directory = tmp_path / "results"
    directory.mkdir()
    write_run(directory, "sim1_free", "free")
    write_run(directory, "sim1_tethered", "tethered")
    return directory


def _embedded(page: str, element: str) -> object:
    """The strict JSON inside ``<script type="application/json" id=element>``."""
    found = re.search(rf'<script type="application/json" id="{element}">(.*?)</script>', page, re.S)
    assert found is not None, element

    def refuse(name: str) -> None:
        raise AssertionError(f"{element} holds {name}: not strict JSON")

    return json.loads(found.group(1), parse_constant=refuse)


def test_view_writes_one_self_contained_html_file(results: Path, tmp_path: Path, capsys):
    out = tmp_path / "replay.html"
    assert main(["view", str(results), "--out", str(out), "--fps", "10", "--quiet"]) == 0
    assert capsys.readouterr().out.strip() == f"wrote {out}"
    page = out.read_text(encoding="utf-8")
    markup = re.sub(r"<script[^>]*>.*?</script>", "<script></script>", page, flags=re.S)
    assert re.search(r"<[^>]*\s(src|href)\s*=", markup) is None  # nothing loaded from elsewhere
    assert "import(" not in markup and "http" not in markup
    viewer = re.findall(r'<script type="module">(.*?)</script>', page, re.S)[0]
    assert re.findall(r"import\((\w+)\)", viewer) == ["libraryUrl"]  # the inlined library only
    data = _embedded(page, "replay-data")
    library = _embedded(page, "three-source")
    vendored = resources.files("tetherheli.viz").joinpath("replay_assets/three.module.min.js")
    assert library == vendored.read_text(encoding="utf-8")  # three.js r170, whole
    assert data["time"] == pytest.approx(np.arange(21) * 0.1)  # 2 s at 10 frames/s
    assert [r["stem"] for r in data["runs"]] == ["sim1_free", "sim1_tethered"]
    assert [r["colour"] for r in data["runs"]] == ["#d62728", "#1f77b4"]  # the figures' colours
    tethered = data["runs"][1]["frames"]
    assert len(tethered["HO"]) == 3 * 21 and len(tethered["quaternion"]) == 4 * 21
    assert tethered["node_count"] == 0 and tethered["nodes"] is None
    assert tethered["tension"][0] == pytest.approx(25.0)
    # the default file is RESULT_DIR/replay.html, listed in the folder's record when it has one
    assert main(["view", str(results), "--quiet"]) == 0
    assert (results / "replay.html").read_text(encoding="utf-8").startswith("<!DOCTYPE html>")


def test_view_errors_are_one_line(results: Path, tmp_path: Path, capsys):
    foreign = tmp_path / "mine.html"
    foreign.write_text("mine")
    cases = [
        ([str(tmp_path / "missing")], "directory"),
        ([str(results), "--out", str(tmp_path / "replay.txt")], ".html"),
        ([str(results), "--out", str(foreign)], "was not written by tetherheli"),
        ([str(results), "--fps", "0", "--out", str(tmp_path / "r.html")], "fps"),
        ([str(results), "--runs", "nope", "--out", str(tmp_path / "r.html")], "nope"),
    ]
    for argv, words in cases:
        assert main(["view", *argv]) == 2, argv
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and words in err, (argv, err)
        assert "Traceback" not in err
    assert foreign.read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine.html", "results"]


def test_non_finite_values_are_null_and_the_base_moves_the_scene():
    n = 11
    t = np.linspace(0.0, 1.0, n)
    q = np.zeros((n, 9))
    q[:, 2] = 10.0
    q[:, 8] = 10.0
    q[5, 0] = np.nan  # a sample the simulator could not compute
    base = np.column_stack([0.0 * t, 0.0 * t, 0.5 * np.sin(2 * np.pi * t)])
    nodes = np.zeros((n, 3, 3))
    nodes[:, 1, 2], nodes[:, 2, 2] = 5.0, 9.7
    from tetherheli import Params

    run = RunData(
        stem="deck", name="deck", configuration="tethered", time=t, q=q,
        wind=np.zeros((n, 3)), tension=np.full(n, 20.0), trim_position=np.array([0, 0, 10.0]),
        helicopter=Params.paper().helicopter, status=0, message="ok", version="test",
        base=base, nodes=nodes,
    )  # fmt: skip
    data = replay_data([run], fps=10)
    json.dumps(data, allow_nan=False)  # strict
    frames = data["runs"][0]["frames"]
    assert frames["HO"][3 * 5] is None and frames["O"][3 * 5] is None
    assert frames["HO"][3 * 2 + 2] == pytest.approx(10.0 + base[2, 2], abs=1e-4)
    assert frames["base"][3 * 2 + 2] == pytest.approx(base[2, 2], abs=1e-4)
    assert frames["node_count"] == 3  # the chain's nodes, moved with the base
    assert frames["nodes"][9 * 2 + 8] == pytest.approx(9.7 + base[2, 2], abs=1e-4)


def test_load_run_reads_the_base_and_the_chain_nodes(tmp_path: Path):
    write_run(tmp_path, "deck", "tethered")
    text = (tmp_path / "deck.csv").read_text().splitlines()
    nodes = [f"node{i}_n{a}" for i in range(2) for a in (1, 2, 3)]
    extra = ["base_n1", "base_n2", "base_n3", *nodes]
    rows = [text[0] + "," + ",".join(extra)]
    for k, line in enumerate(text[1:]):
        rows.append(line + "," + ",".join(["0.0", "0.0", repr(0.01 * k)] + ["1.0"] * 6))
    (tmp_path / "deck.csv").write_text("\n".join(rows) + "\n")
    run = load_run(tmp_path, "deck")
    assert run.base_moves and run.base[3, 2] == pytest.approx(0.03)
    assert run.nodes is not None and run.nodes.shape == (len(run.time), 2, 3)
    assert np.allclose(run.world_position[:, 2], run.position[:, 2] + run.base[:, 2])


def _browser() -> str | None:
    for name in BROWSERS:
        found = shutil.which(name)
        if found:
            return found
    return None


def _run_browser(browser: str, profile: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [browser, *BROWSER_FLAGS, f"--user-data-dir={profile}", *args],
        capture_output=True,
        text=True,
        timeout=180,
        check=False,
    )


@pytest.mark.slow
def test_replay_renders_in_headless_chromium(results: Path, tmp_path: Path):
    """The page loads with no error (its #status, which counts window errors and
    console.error, and Chromium's console log) and draws different pictures at two times."""
    browser = _browser()
    if browser is None:
        pytest.skip(f"no Chromium or Chrome found (looked for {', '.join(BROWSERS)})")
    out = write_replay(results, tmp_path / "replay.html", fps=10)
    url = out.as_uri()
    dom = _run_browser(
        browser, tmp_path / "profile-dom", "--enable-logging=stderr", "--v=0", "--dump-dom",
        f"{url}#t=0.5",
    )  # fmt: skip
    status = re.search(r'<div id="status"([^>]*)>([^<]*)<', dom.stdout)
    assert status is not None, dom.stderr[-2000:]
    assert 'data-state="ready"' in status.group(1), status.group(2)
    assert 'data-errors="0"' in status.group(1) and 'data-frame="5"' in status.group(1)
    console = [line for line in dom.stderr.splitlines() if ":CONSOLE" in line]
    assert not [c for c in console if "Uncaught" in c or "Error" in c], console
    pictures = []
    for t in (0.0, 1.7):
        png = tmp_path / f"t{t}.png"
        _run_browser(browser, tmp_path / f"profile-{t}", f"--screenshot={png}", f"{url}#t={t}")
        with Image.open(png) as im:
            pictures.append(np.asarray(im.convert("RGB"), dtype=int))
    a, b = pictures
    assert a.shape == b.shape == (560, 800, 3)
    assert a.std() > 5.0  # not a blank page
    changed = np.abs(a - b).max(axis=2) > 30
    assert changed.mean() > 0.002, changed.mean()  # the helicopter moved, the clock changed

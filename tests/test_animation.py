"""3-D animation of saved runs (tetherheli.viz.animation), on synthetic result files."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from matplotlib import animation
from PIL import Image

from tetherheli import Params
from tetherheli._io import OUTPUT_RECORD, OutputPathError, record_outputs
from tetherheli.errors import ParameterError
from tetherheli.resources import MEMORY_LIMIT_ENV, ResourceLimitError
from tetherheli.viz.animation import (
    MAX_FRAMES,
    RunData,
    animate,
    direction_cosines,
    helicopter_points,
    list_runs,
    load_run,
    render_frame,
)
from tetherheli.viz.scene import _Scene

COLUMNS = (
    "t", "q4", "q5", "q6", "q7", "q8", "q9", "u1", "u2", "u3", "u4", "u5", "u6", "LN",
    "q1", "q2", "q3", "fMR3", "tMR1", "tMR2", "fTR2", "C1_ffwd", "C2_ffwd", "TC", "RC",
    "Fw1", "Fw2", "Fw3",
)  # fmt: skip


def write_run(
    directory: Path, stem: str, configuration: str, *, duration: float = 2.0, dt: float = 0.01
) -> None:
    """A helicopter swinging on a 10 m tether (or hovering free), saved in the format of
    ``SimulationResult.save``: eqs 43-45 give HO from q7, q8, q9 and the attitude."""
    h = Params.paper().helicopter
    t = np.arange(round(duration / dt) + 1) * dt
    w = 2.0 * np.pi * 0.5
    q4 = 0.09 + 0.05 * np.sin(w * t)
    q5 = 0.04 * np.cos(w * t)
    q6 = 0.1 * np.sin(0.5 * w * t)
    q7 = 0.08 * np.sin(w * t)
    q8 = 0.05 * np.sin(w * t + 0.3)
    q9 = np.full_like(t, 10.0)
    c3 = np.column_stack([np.sin(q8), -np.sin(q7) * np.cos(q8), np.cos(q7) * np.cos(q8)])
    f3 = direction_cosines(q4, q5, q6)[:, :, 2]
    HO = q9[:, None] * c3 - h.tether_arm * f3
    tension = 25.0 + 10.0 * np.sin(w * t) if configuration == "tethered" else 0.0 * t
    if configuration == "tethered":
        tension[t > 0.75 * duration] = 0.0  # a slack spell
    wind = np.column_stack([20.0 * (t > 0.5), 0.0 * t, 0.0 * t])
    cols = dict.fromkeys(COLUMNS, np.zeros_like(t))
    cols.update(
        t=t,
        q4=q4,
        q5=q5,
        q6=q6,
        q7=q7,
        q8=q8,
        q9=q9,
        q1=HO[:, 0],
        q2=HO[:, 1],
        q3=HO[:, 2],
        TC=tension,
        Fw1=wind[:, 0],
        Fw2=wind[:, 1],
        Fw3=wind[:, 2],
        LN=q9 - 0.625,
    )
    data = np.column_stack([cols[c] for c in COLUMNS])
    lines = [",".join(COLUMNS)] + [",".join(repr(float(v)) for v in row) for row in data]
    (directory / f"{stem}.csv").write_text("\n".join(lines) + "\n")
    meta = {
        "tetherheli_version": "0.1.0",
        "status": 0,
        "message": "ok",
        "configuration": {
            "name": stem,
            "configuration": configuration,
            "duration": duration,
            "params": Params.paper().to_dict(),
        },
        "trim": {
            "state": dict.fromkeys(COLUMNS[1:14], 0.0),
            "input": dict.fromkeys(COLUMNS[17:21], 0.0),
            "output": {"q1": 0.0, "q2": -0.0189, "q3": 10.2, "q6": 0.0},
        },
    }
    (directory / f"{stem}.json").write_text(json.dumps(meta))


@pytest.fixture
def results(tmp_path: Path) -> Path:
    directory = tmp_path / "results"
    directory.mkdir()
    write_run(directory, "sim1_free", "free")
    write_run(directory, "sim1_tethered", "tethered")
    (directory / "notes.txt").write_text("not a run\n")
    return directory


# --- geometry -----------------------------------------------------------------------------


def test_direction_cosines_is_a_rotation_with_table_I_columns():
    q = np.array([[0.3, -0.2, 1.1], [0.0, 0.0, 0.0], [-1.0, 0.7, -2.5]])
    R = direction_cosines(q[:, 0], q[:, 1], q[:, 2])
    assert R.shape == (3, 3, 3)
    np.testing.assert_allclose(
        R @ np.swapaxes(R, 1, 2), np.broadcast_to(np.eye(3), R.shape), atol=1e-14
    )
    np.testing.assert_allclose(np.linalg.det(R), 1.0)
    # body-1-2-3: R = R1(q4) R2(q5) R3(q6), built here from elementary rotations
    q4, q5, q6 = q[0]
    c, s = np.cos, np.sin
    R1 = np.array([[1, 0, 0], [0, c(q4), -s(q4)], [0, s(q4), c(q4)]])
    R2 = np.array([[c(q5), 0, s(q5)], [0, 1, 0], [-s(q5), 0, c(q5)]])
    R3 = np.array([[c(q6), -s(q6), 0], [s(q6), c(q6), 0], [0, 0, 1]])
    np.testing.assert_allclose(R[0], R1 @ R2 @ R3, atol=1e-15)
    # f3 = [s5, -s4 c5, c4 c5] (SPEC, eqs 43-45)
    np.testing.assert_allclose(R[0][:, 2], [s(q5), -s(q4) * c(q5), c(q4) * c(q5)])


def test_points_at_zero_attitude_lie_on_the_axes_with_table_II_offsets():
    h = Params.paper().helicopter
    pts = helicopter_points([1.0, 2.0, 10.0], [0.0, 0.0, 0.0], h)
    N_p_O = np.array([1.0, 2.0, 10.0 + 0.0954049])  # dO-HO,3 = -0.0954049 m (eq 3)
    np.testing.assert_allclose(pts.N_p_HO, [1.0, 2.0, 10.0])
    np.testing.assert_allclose(pts.N_p_O, N_p_O, atol=1e-7)
    np.testing.assert_allclose(pts.N_p_MRO - pts.N_p_O, [0.0, 0.0, 0.166])
    np.testing.assert_allclose(pts.N_p_TRO - pts.N_p_O, [-1.08, 0.0, 0.0])
    np.testing.assert_allclose(pts.N_p_P - pts.N_p_O, [0.0, 0.0, -0.3])
    # so with all angles zero P sits (dO-P,3 - dO-HO,3) = -0.2045951 m below HO
    np.testing.assert_allclose(pts.N_p_P, [1.0, 2.0, 10.0 - 0.2045951], atol=1e-7)


def test_tether_attachment_is_q9_c3_for_a_tethered_state():
    """P = q9 c3 (eq 45) when HO = q9 c3 - (dO-P,3 - dO-HO,3) f3 (eqs 43-44)."""
    h = Params.paper().helicopter
    rng = np.random.default_rng(7)
    for _ in range(5):
        q4, q5, q6, q7, q8 = rng.uniform(-0.6, 0.6, 5)
        q9 = rng.uniform(2.0, 20.0)
        c3 = np.array([np.sin(q8), -np.sin(q7) * np.cos(q8), np.cos(q7) * np.cos(q8)])
        f3 = np.array([np.sin(q5), -np.sin(q4) * np.cos(q5), np.cos(q4) * np.cos(q5)])
        HO = q9 * c3 - (h.d_O_P3 - h.d_O_HO3) * f3
        pts = helicopter_points(HO, [q4, q5, q6], h)
        np.testing.assert_allclose(pts.N_p_P, q9 * c3, atol=1e-12)
        np.testing.assert_allclose(np.linalg.norm(pts.N_p_TRO - pts.N_p_O), 1.08)


# --- loading ------------------------------------------------------------------------------


def test_load_run_reads_the_saved_format(results: Path):
    assert list_runs(results) == ["sim1_free", "sim1_tethered"]
    run = load_run(results, "sim1_tethered")
    assert isinstance(run, RunData)
    assert run.configuration == "tethered" and run.tethered and run.name == "sim1_tethered"
    assert run.time.shape == (201,) and run.q.shape == (201, 9) and run.wind.shape == (201, 3)
    np.testing.assert_allclose(run.points().N_p_P, run.q[:, 8:9] * np.column_stack([
        np.sin(run.q[:, 7]), -np.sin(run.q[:, 6]) * np.cos(run.q[:, 7]),
        np.cos(run.q[:, 6]) * np.cos(run.q[:, 7]),
    ]), atol=1e-12)  # fmt: skip
    np.testing.assert_allclose(run.trim_position, [0.0, -0.0189, 10.2])
    assert not run.q.flags.writeable
    with pytest.raises(ParameterError, match="several"):
        load_run(results)


def test_missing_and_empty_directories_are_parameter_errors(tmp_path: Path):
    with pytest.raises(ParameterError, match="existing directory"):
        load_run(tmp_path / "nowhere")
    with pytest.raises(ParameterError, match="existing directory"):
        animate(tmp_path / "nowhere", tmp_path / "a.gif")
    (tmp_path / "lonely.csv").write_text("t,q1\n0,0\n")  # a CSV without its JSON
    with pytest.raises(ParameterError, match=r"result pairs") as info:
        load_run(tmp_path)
    assert str(tmp_path) in str(info.value) and "\n" not in str(info.value)
    with pytest.raises(ParameterError, match=r"result pairs"):
        animate(tmp_path, tmp_path / "a.gif")
    assert not (tmp_path / "a.gif").exists()


@pytest.mark.parametrize(
    ("csv_text", "match"),
    [
        ("t,q1\n0,0\n", "csv header"),
        (",".join(COLUMNS) + "\n", "no data rows"),
        (",".join(COLUMNS) + "\n" + ",".join(["0"] * 5) + "\n", "line 2"),
        (",".join(COLUMNS) + "\n" + ",".join(["x"] * len(COLUMNS)) + "\n", "numbers"),
        (",".join(COLUMNS) + "\n" + ",".join(["nan"] * len(COLUMNS)) + "\n", "finite"),
    ],
)
def test_malformed_csv_is_a_parameter_error(results: Path, csv_text: str, match: str):
    (results / "sim1_free.csv").write_text(csv_text)
    with pytest.raises(ParameterError, match=match) as info:
        load_run(results, "sim1_free")
    assert "sim1_free.csv" in str(info.value)


def test_an_empty_parquet_run_is_named_as_parquet(results: Path):
    pd = pytest.importorskip("pandas")
    pytest.importorskip("pyarrow")
    (results / "sim1_free.csv").unlink()
    pd.DataFrame({c: np.zeros(0) for c in COLUMNS}).to_parquet(results / "sim1_free.parquet")
    with pytest.raises(ParameterError, match="no data rows") as info:
        load_run(results, "sim1_free")
    assert "sim1_free.parquet" in str(info.value) and "parquet" in str(info.value).split()[0]


def test_unknown_stem_names_the_available_runs(results: Path):
    with pytest.raises(ParameterError, match="sim1_free"):
        load_run(results, "sim9")


# --- rendering ----------------------------------------------------------------------------


def test_gif_has_the_expected_frames(results: Path, tmp_path: Path):
    out = tmp_path / "anim.gif"
    # 2 s at fps * speed = 2.5 frames per simulated second: frames at 0, 0.4, ..., 2.0 s
    written = animate(results, out, fps=5, speed=2.0, dpi=30)
    assert written == out
    with Image.open(out) as im:
        assert im.format == "GIF"
        assert im.n_frames == 6
        assert im.size == (300, 180)  # 10 x 6 inch at 30 dpi
    assert sorted(p.name for p in tmp_path.iterdir()) == ["anim.gif", "results"]
    umask = os.umask(0o022)
    os.umask(umask)
    assert out.stat().st_mode & 0o777 == 0o666 & ~umask  # not the 0600 of a temporary file


def test_animation_frames_match_a_full_redraw(results: Path, tmp_path: Path):
    """Frames draw only the moving parts over a stored background; they must look like a
    frame drawn from scratch (render_frame), up to the GIF palette."""
    gif = animate(results, tmp_path / "two.gif", fps=1, speed=2.0, dpi=40)  # frames at 0, 2 s
    png = render_frame(results, tmp_path / "end.png", time=2.0, dpi=40)
    with Image.open(gif) as im:
        im.seek(1)
        fast = np.asarray(im.convert("RGB"), dtype=int)
    with Image.open(png) as im:
        full = np.asarray(im.convert("RGB"), dtype=int)
    assert fast.shape == full.shape
    differs = np.abs(fast - full).max(axis=2) > 60
    assert differs.mean() < 0.002


def test_four_runs_are_overlaid(tmp_path: Path):
    """The paper job's directory: sim1/sim2, free and tethered, drawn in one animation."""
    for stem in ("sim1_free", "sim1_tethered", "sim2_free", "sim2_tethered"):
        write_run(tmp_path, stem, stem.split("_")[1], duration=0.5)
    out = animate(tmp_path, tmp_path / "all.gif", fps=4, dpi=20)
    with Image.open(out) as im:
        assert im.n_frames == 3


def test_max_frames_caps_the_frame_count(results: Path, tmp_path: Path):
    out = animate(
        results, tmp_path / "capped.gif", stems=["sim1_tethered"], fps=50, max_frames=4, dpi=20
    )
    with Image.open(out) as im:
        assert im.n_frames == 4
        # the frame rate drops so that the run still plays in real time: 2 s / 3 intervals
        assert im.info["duration"] == pytest.approx(1000 * 2.0 / 3, abs=10)


def test_failed_rendering_leaves_no_file(results: Path, tmp_path: Path, monkeypatch):
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    out = out_dir / "broken.gif"

    def boom(self, *args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(_Scene, "render", boom)  # a GIF's frames are drawn by blitting
    with pytest.raises(RuntimeError, match="disk full"):
        animate(results, out, fps=2, dpi=20)
    assert list(out_dir.iterdir()) == []

    # failing while the file is being written: an existing file (one tetherheli wrote, in an
    # output directory it recorded) is left untouched
    monkeypatch.undo()
    record_outputs(out_dir, [], writer="simulate")
    animate(results, out, fps=2, dpi=20)
    old = out.read_bytes()
    monkeypatch.setattr(Image.Image, "save", boom)  # the GIF's writing
    with pytest.raises(RuntimeError, match="disk full"):
        animate(results, out, fps=2, dpi=20)
    assert sorted(p.name for p in out_dir.iterdir()) == [OUTPUT_RECORD, "broken.gif"]
    assert out.read_bytes() == old


def test_never_overwrites_a_file_it_did_not_write(results: Path, tmp_path: Path):
    """Issue 9: an animation never replaces a user's file; one it wrote may be re-rendered."""
    mine = tmp_path / "movie.gif"
    mine.write_bytes(b"the user's own movie")
    with pytest.raises(OutputPathError, match="not written by tetherheli"):
        animate(results, mine, fps=2, dpi=20)
    assert mine.read_bytes() == b"the user's own movie"
    # in a tetherheli output directory the animation is recorded ...
    record_outputs(results, [], writer="simulate")
    out = results / "animation.gif"
    animate(results, out, fps=2, dpi=20)
    animate(results, out, fps=2, dpi=20)  # ... so it may be rendered again
    out.write_bytes(b"edited by the user")  # changed since: the user's now
    with pytest.raises(OutputPathError, match="changed since"):
        animate(results, out, fps=2, dpi=20)


def test_render_options_are_bounded_before_rendering(results: Path, tmp_path: Path, monkeypatch):
    """Issue 9: fps, frames and resolution are capped, and a GIF's frames must fit the budget."""
    for bad, match in (
        ({"fps": 101}, "fps"),
        ({"max_frames": MAX_FRAMES + 1}, "max_frames"),
        ({"dpi": 601}, "dpi"),
    ):
        with pytest.raises(ParameterError, match=match):
            animate(results, tmp_path / "a.gif", **bad)
    monkeypatch.setenv(MEMORY_LIMIT_ENV, "50M")
    with pytest.raises(ResourceLimitError, match=r"frames at dpi = 80 needs about .* 47\.7 MiB"):
        animate(results, tmp_path / "a.gif", fps=100, max_frames=MAX_FRAMES)
    assert not (tmp_path / "a.gif").exists()


def test_output_format_and_options_are_checked(results: Path, tmp_path: Path, monkeypatch):
    with pytest.raises(ParameterError, match=r"'\.gif'"):
        animate(results, tmp_path / "a.avi")
    monkeypatch.setattr(animation.writers, "is_available", lambda name: name != "ffmpeg")
    with pytest.raises(ParameterError, match="ffmpeg") as info:
        animate(results, tmp_path / "a.mp4")
    assert ".mp4" in str(info.value) and ".gif" in str(info.value)
    for bad in ({"fps": 0}, {"speed": -1.0}, {"max_frames": 2.5}, {"dpi": float("nan")}):
        with pytest.raises(ParameterError):
            animate(results, tmp_path / "a.gif", **bad)
    with pytest.raises(ParameterError, match="existing directory"):
        animate(results, tmp_path / "missing" / "a.gif")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results"]


def test_render_frame_writes_a_png(results: Path, tmp_path: Path):
    out = render_frame(results, tmp_path / "frame.png", time=1.0, dpi=30)
    with Image.open(out) as im:
        assert im.format == "PNG" and im.size == (300, 180)
    with pytest.raises(ParameterError, match="time"):
        render_frame(results, tmp_path / "late.png", time=5.0)
    with pytest.raises(ParameterError, match=r"\.png"):
        render_frame(results, tmp_path / "frame.xyz", time=1.0)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frame.png", "results"]


# --- the moving deck, the run lines and the layout (issue 47 item 6) ------------------------


def _with_base(directory: Path, stem: str, heave: float) -> None:
    """Add a heaving base (base_n1..3, 2 s period) to a saved run's CSV."""
    path = directory / f"{stem}.csv"
    header, *rows = path.read_text().splitlines()
    out = [header + ",base_n1,base_n2,base_n3"]
    for row in rows:
        t = float(row.split(",")[0])
        out.append(row + f",0.0,0.0,{float(heave * np.sin(np.pi * t))!r}")
    path.write_text("\n".join(out) + "\n")


def test_a_moving_base_moves_the_deck_winch_and_helicopter(tmp_path: Path):
    write_run(tmp_path, "deck", "free")
    _with_base(tmp_path, "deck", 2.0)
    run = load_run(tmp_path, "deck")
    assert run.base_moves
    times = np.array([0.0, 0.5, 1.5])
    scene = _Scene([run], times, rotor_radius=0.9, wind_scale=None, dpi=20)
    assert scene.whole and len(scene.decks) == 1  # a free run over a deck: the whole scene too
    winch = scene.decks[0].winch
    heights = []
    for k in range(len(times)):
        scene.update(k)
        heights.append(float(np.asarray(winch.get_data_3d()[2])[0]))
        sample = round(100 * times[k])
        assert scene.shapes[0].HO[k, 2] == pytest.approx(run.world_position[sample, 2])
    assert heights == pytest.approx([0.0, 2.0, -2.0], abs=1e-9)
    gif = animate(tmp_path, tmp_path / "deck.gif", fps=2, speed=1.0, dpi=30)
    with Image.open(gif) as im:
        pictures = []
        for k in (1, 3):
            im.seek(k)
            pictures.append(np.asarray(im.convert("RGB"), dtype=int))
    assert (np.abs(pictures[0] - pictures[1]).max(axis=2) > 60).any()


def test_run_lines_fit_the_figure_and_nothing_overlaps(tmp_path: Path):
    """Long run names and a failure message are cut to fit; the clock, the run lines, the
    panels' labels, the colour bar and the legend keep apart."""
    long = "a_scenario_with_a_rather_long_descriptive_name"
    for config in ("free", "tethered"):
        write_run(tmp_path, f"{long}_{config}", config)
    meta_path = tmp_path / f"{long}_tethered.json"
    meta = json.loads(meta_path.read_text())
    meta.update(status=4, message="the integration failed: a state was not finite " * 3)
    meta_path.write_text(json.dumps(meta))
    runs = [load_run(tmp_path, f"{long}_{c}") for c in ("free", "tethered")]
    scene = _Scene(runs, np.array([0.0, 2.0]), rotor_radius=0.9, wind_scale=None, dpi=80)
    scene.update(1)
    fig = scene.fig
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    page = fig.bbox
    texts = [scene.clock, *scene.labels]
    boxes = [t.get_window_extent(renderer) for t in texts]
    for t, box in zip(texts, boxes, strict=True):
        assert t.get_text() and page.x0 <= box.x0 and box.x1 <= page.x1, t.get_text()
        assert page.y0 <= box.y0 and box.y1 <= page.y1, t.get_text()
    assert scene.labels[1].get_text().endswith("...")  # the long failure message, cut
    for i, a in enumerate(boxes):
        for b in boxes[i + 1 :]:
            assert not a.overlaps(b)
    legend = fig.legends[0].get_window_extent(renderer)
    colour_bar = next(ax for ax in fig.axes if not hasattr(ax, "zaxis"))
    bar = colour_bar.get_tightbbox(renderer)
    close_up = scene.views[-1].ax
    labels = [
        close_up.zaxis.label.get_window_extent(renderer),
        close_up.yaxis.label.get_window_extent(renderer),
        *(t.get_window_extent(renderer) for t in close_up.zaxis.get_ticklabels() if t.get_text()),
    ]
    for box in labels:
        assert not box.overlaps(bar)
    for view in scene.views:
        for axis in (view.ax.xaxis, view.ax.yaxis):
            assert not axis.label.get_window_extent(renderer).overlaps(legend)
        assert not view.ax.title.get_window_extent(renderer).overlaps(boxes[-1])
    for box in boxes:
        assert not box.overlaps(legend)

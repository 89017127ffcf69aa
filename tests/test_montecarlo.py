"""Monte Carlo: reproducible draws, resumable chunks, strict configuration."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from tetherheli._io import read_json
from tetherheli.cli import main
from tetherheli.errors import ParameterError
from tetherheli.report import run_montecarlo
from tetherheli.runs import simulate
from tetherheli.runs.batch import run_batch
from tetherheli.status import Status
from tetherheli.studies.montecarlo import load_montecarlo, montecarlo_config_from_dict

ROOT = Path(__file__).resolve().parents[1]

SHORT = """
name = "mc_short"
duration = 5.0
[[wind]]
type = "pulse"
start = 1.0
duration = 0.5
magnitude = 20.0
direction = [1.0, 0.0, 0.0]
[[wind]]
type = "sine"
amplitude = 10.0
frequency = 0.5
start = 2.0
direction = [1.0, 0.0, 0.0]
[montecarlo]
runs = 8
seed = 7
amplitude_std_percent = 20.0
direction_std_deg = 10.0
random_phase = true
start_jitter_s = 0.5
params = { "helicopter.m_F" = 5.0, "tether.K_C" = 10.0 }
"""


@pytest.fixture
def short_file(tmp_path: Path) -> Path:
    p = tmp_path / "mc.toml"
    p.write_text(SHORT)
    return p


def _run(path: Path, out: Path, **kw):
    base, config = load_montecarlo(path)
    return run_montecarlo(base, config, out, chunk_size=3, progress=False, **kw)


def _rows(out: Path) -> list[dict[str, str]]:
    with open(out / "results.csv", newline="") as fh:
        return list(csv.DictReader(fh))


def _chunks_of(out: Path) -> list[Path]:
    return sorted((out / "partial").glob("chunk_*.csv"))


def test_outputs_and_equal_seeds_equal_tables(short_file, tmp_path):
    s1 = _run(short_file, tmp_path / "a")
    _run(short_file, tmp_path / "b", workers=1)
    a = (tmp_path / "a" / "results.csv").read_bytes()
    assert a == (tmp_path / "b" / "results.csv").read_bytes()
    rows = _rows(tmp_path / "a")
    assert len(rows) == 16
    assert [r["configuration"] for r in rows[:2]] == ["free", "tethered"]
    assert [int(r["run"]) for r in rows[::2]] == list(range(8))
    assert {r["seed_entropy"] for r in rows} == {"7"}
    assert [r["spawn_key"] for r in rows[::2]] == [str(i) for i in range(8)]
    assert all(r["status"] == "0" for r in rows)
    # the free and tethered runs of a draw share its dispersed values
    for f, t in zip(rows[::2], rows[1::2], strict=True):
        assert f["amplitude_scale"] == t["amplitude_scale"]
        assert f["value:tether.K_C"] == t["value:tether.K_C"]
        assert float(f["tension_max"]) == 0.0 and float(t["tension_min"]) > 20.0
    factors = np.array([float(r["factor:helicopter.m_F"]) for r in rows])
    assert np.all(np.abs(factors - 1.0) <= 0.05) and np.ptp(factors) > 0
    summary = read_json(tmp_path / "a" / "summary.json")  # "Infinity" strings: floats
    assert summary == s1 and summary["N"] == 8 and summary["seed"] == 7
    assert summary["statistics"]["free"]["completed"] == 8
    assert "p95" in summary["statistics"]["tethered"]["peak_q1"]
    for name in ("peak_q1_hist.png", "peak_q1_cdf.png", "peak_q1_paired.png"):
        assert (tmp_path / "a" / name).stat().st_size > 1000
    # another seed gives other draws
    base, config = load_montecarlo(short_file)
    other = run_montecarlo(
        base, config.__class__(**{**config.__dict__, "seed": 8}), tmp_path / "c", progress=False
    )
    assert other is not None
    assert (tmp_path / "c" / "results.csv").read_bytes() != a


def test_row_equals_a_single_simulation(short_file, tmp_path):
    """Row 3 (draw 1, tethered) is the dispersed scenario run alone with the nominal gain."""
    from tetherheli.studies.montecarlo import draw

    base, config = load_montecarlo(short_file)
    _run(short_file, tmp_path / "a")
    row = _rows(tmp_path / "a")[3]
    child = np.random.SeedSequence(7).spawn(8)[1]
    d = draw(base, config, child, 1)
    assert float(row["value:helicopter.m_F"]) == d.scenario.params.helicopter.m_F
    b = run_batch([d.scenario], design_params=base.params)
    assert float(row["peak_q1"]) == b.metrics(0)["peak_q1"]
    # with nominal parameters the batch is exactly simulate()
    nominal = d.scenario.replace(params=base.params)
    single = simulate(nominal)
    dev = single.outputs[:, 0] - single.trim_output[0]
    assert run_batch([nominal]).metrics(0)["peak_q1"] == pytest.approx(
        float(np.max(np.abs(dev))), rel=1e-12
    )


@pytest.mark.usefixtures("blank_figures")  # the chunks under test, not the plots
def test_resume_after_interrupt_equals_uninterrupted(short_file, uninterrupted, tmp_path, capsys):
    assert _run(short_file, tmp_path / "r", max_chunks=1) is None
    assert not (tmp_path / "r" / "results.csv").exists()
    assert len(list((tmp_path / "r" / "partial").glob("chunk_*.csv"))) == 1
    assert _run(short_file, tmp_path / "r", max_chunks=1) is None
    assert len(list((tmp_path / "r" / "partial").glob("chunk_*.csv"))) == 2
    assert _run(short_file, tmp_path / "r") is not None
    assert (tmp_path / "r" / "results.csv").read_bytes() == uninterrupted
    # a larger N extends the finished job: the first draws are reused, the table equals a
    # fresh run of the larger N
    base, config = load_montecarlo(short_file)
    more = config.__class__(**{**config.__dict__, "runs": 11})
    before = {p.name: p.stat().st_mtime_ns for p in (tmp_path / "r" / "partial").glob("c*")}
    run_montecarlo(base, more, tmp_path / "r", chunk_size=3, progress=False)
    run_montecarlo(base, more, tmp_path / "fresh", chunk_size=3, progress=False)
    assert (tmp_path / "r" / "results.csv").read_bytes() == (
        tmp_path / "fresh" / "results.csv"
    ).read_bytes()
    after = {p.name: p.stat().st_mtime_ns for p in (tmp_path / "r" / "partial").glob("c*")}
    assert all(
        after[name] == t for name, t in before.items() if name != "chunk_000000006_000000008.csv"
    )
    # a different job may not reuse the folder
    with pytest.raises(ParameterError, match=r"partial/job\.json"):
        run_montecarlo(base, config, tmp_path / "r", chunk_size=4, progress=False)


def test_the_study_returns_what_the_report_writes(short_file, tmp_path):
    """``run_montecarlo_chunks`` writes no results folder and returns the finished job: its
    verified chunks are results.csv's rows and its summary is summary.json, as the report
    (``report.montecarlo``) writes them; a chunk changed after the job verified it stops the
    reading with a line naming the file."""
    from tetherheli.errors import TetherheliError
    from tetherheli.studies.montecarlo import run_montecarlo_chunks
    from tetherheli.studies.montecarlo.runner import MonteCarloColumns

    base, config = load_montecarlo(short_file)
    out = tmp_path / "j"
    job = run_montecarlo_chunks(base, config, out, chunk_size=3, progress=False)
    assert job is not None and not (out / "results.csv").exists()
    columns = MonteCarloColumns(job.header)
    rows = "".join(job.chunks(columns))
    summary = json.loads(json.dumps(job.summarize(columns.arrays())))
    assert _run(short_file, out) == summary
    assert (out / "results.csv").read_text() == ",".join(job.header) + "\n" + rows
    first = _chunks_of(out)[0]
    first.write_text(first.read_text().replace(",free,", ",tethered,", 1))
    with pytest.raises(TetherheliError, match=rf"{first.name} .* after it was verified"):
        list(job.chunks())


def test_progress_on_stderr_is_one_line_off_a_terminal(short_file, tmp_path, capsys):
    base, config = load_montecarlo(short_file)
    run_montecarlo(base, config, tmp_path / "p", chunk_size=4, progress=True)
    err = capsys.readouterr().err
    assert "\r" not in err and len(err.splitlines()) == 1
    assert err.startswith("montecarlo: 8/8 draws in ") and "draws/s" in err


@pytest.mark.parametrize(
    ("table", "match"),
    [
        ({"runs": 0}, "montecarlo.runs"),
        ({"runs": 2.5}, "montecarlo.runs"),
        ({"amplitude_std_percent": -1.0}, "amplitude_std_percent"),
        ({"amplitude_std_percent": 150.0}, "amplitude_std_percent"),
        ({"direction_std_deg": 720.0}, "direction_std_deg"),
        ({"start_jitter_s": -0.1}, "start_jitter_s"),
        ({"start_jitter_s": math.inf}, "start_jitter_s"),
        ({"random_phase": 1}, "random_phase"),
        ({"params": {"helicopter.m_F": 100.0}}, "helicopter.m_F"),
        ({"params": {"helicopter.m_F": -5.0}}, "helicopter.m_F"),
        ({"params": {"helicopter.mass": 5.0}}, "helicopter.mass"),
        ({"params": {"m_F": 5.0}}, "m_F"),
        ({"params": 5.0}, "montecarlo.params"),
        ({"amplitude": 5.0}, "montecarlo.amplitude"),
    ],
)
def test_bad_config_one_line_error(table, match):
    with pytest.raises(ParameterError, match=match) as info:
        montecarlo_config_from_dict(table, source="f.toml")
    assert "\n" not in str(info.value) and str(info.value).startswith("f.toml: ")


def test_file_errors(tmp_path):
    p = tmp_path / "nomc.toml"
    p.write_text('name = "x"\n')
    with pytest.raises(ParameterError, match=r"\[montecarlo\] table"):
        load_montecarlo(p)
    p.write_text('[montecarlo]\nruns = 4\n[[wind]]\ntype = "turbulence"\n')
    with pytest.raises(ParameterError):
        load_montecarlo(p)
    with pytest.raises(ParameterError, match="file"):
        load_montecarlo(tmp_path / "missing.toml")


def test_cli_subcommand(short_file, tmp_path, capsys):
    from tetherheli import cli

    out = tmp_path / "o"
    for bad, word in (("--runs", "--runs"), ("--chunk-size", "--chunk-size")):
        assert cli.main(["montecarlo", str(short_file), "--out", str(out), bad, "0"]) == 2
        err = capsys.readouterr().err
        assert word in err and len(err.strip().splitlines()) == 1
    assert not out.exists()
    args = ["montecarlo", str(short_file), "--out", str(out), "--runs", "4"]
    assert cli.main([*args, "--quiet", "--chunk-size", "2"]) == 0
    assert "completed 4/4" in capsys.readouterr().out
    # an unreachable scheduler: one line, exit 2, nothing written
    out2 = tmp_path / "o2"
    code = cli.main(
        [*args[:3], str(out2), "--scheduler", "tcp://127.0.0.1:9", "--connect-timeout", "1"]
    )
    err = capsys.readouterr().err
    assert code == 2 and "scheduler" in err and len(err.strip().splitlines()) == 1
    assert not out2.exists()


def test_shipped_scenario_loads():
    base, config = load_montecarlo(ROOT / "scenarios" / "montecarlo_paper_sim1.toml")
    assert base.duration == 60.0 and config.runs == 1000
    assert dict(config.params) == {
        "helicopter.m_F": 5.0,
        "helicopter.I_F11": 10.0,
        "tether.K_C": 10.0,
    }
    assert config.amplitude_std_percent == 20.0 and config.direction_std_deg == 10.0
    assert config.start_jitter_s == 0.5


TURBULENT = """
name = "mc_turbulence"
duration = 5.0
[wind]
type = "turbulence"
seed = 1
duration = 5.0
dt = 0.01
N_v_mean_wind = [5.0, 0.0, 0.0]
[wind.model]
type = "gauss_markov"
gain = [1.5, 1.5, 0.7]
[wind.drag]
cd_area_m2 = [0.4, 0.4, 0.8]
[montecarlo]
runs = 4
seed = 11
direction_std_deg = 90.0
"""


def test_turbulence_gets_a_fresh_series_per_draw(tmp_path):
    """Gust statistics: draw i flies gusts from SeedSequence(seed) with spawn key (i, 0),
    its mean wind rotated by the direction draw; rows equal the drawn scenarios run alone."""
    from tetherheli.studies.montecarlo import draw
    from tetherheli.wind import Turbulence

    f = tmp_path / "t.toml"
    f.write_text(TURBULENT)
    base, config = load_montecarlo(f)
    summary = run_montecarlo(base, config, tmp_path / "o", chunk_size=2, progress=False)
    assert summary["statistics"]["tethered"]["completed"] == 4
    rows = _rows(tmp_path / "o")
    children = np.random.SeedSequence(11).spawn(4)
    winds = []
    for i in range(4):
        d = draw(base, config, children[i], i)
        w = d.scenario.wind
        assert isinstance(w, Turbulence) and w.seed == 11 and w.spawn_key == (i, 0)
        ang = math.radians(d.direction_deg)
        assert w.N_v_mean_wind[:2] == pytest.approx((5 * math.cos(ang), 5 * math.sin(ang)))
        winds.append(w.gust_velocity(np.linspace(0.0, 5.0, 11)))
        tethered = run_batch([d.scenario], design_params=base.params)
        assert float(rows[2 * i + 1]["rms_q1"]) == tethered.metrics(0)["rms_q1"]
    assert not np.array_equal(winds[0], winds[1])


# --- seeds in O(chunk) memory (issue 9, section 3) -----------------------------------------

#: The dispersion columns of SHORT (free rows) as written by the code that spawned all N seeds
#: up front (``SeedSequence(7).spawn(8)``), before seeds were made per chunk.
SHORT_DRAWS_BEFORE = """\
0,7,0,0.8739864150842441,14.650846344213505,3.7155686524197566,1.068178641806855,1.0229339666876247,0.9338322176008053,12.275207600251496,37.35328870403221
1,7,1,1.2803820241263577,8.534203299688002,1.399195875822633,-0.028511756665739182,0.9594485779403863,0.9757489110738109,11.513382935284636,39.02995644295244
2,7,2,1.0078970033013877,11.078549331761538,0.21528692685972883,0.43654980682859773,1.0142855785716158,0.9137481382518305,12.17142694285939,36.549925530073224
3,7,3,0.7968475323834981,-9.11867698857605,0.07361399115717338,0.07158146330774931,0.9725423860851911,1.0066830095493609,11.670508633022292,40.267320381974436
4,7,4,1.0981014733216479,-6.028726521667189,3.2406223060272237,-0.5896121875799888,1.0269672858872085,0.9127079367170076,12.323607430646502,36.5083174686803
5,7,5,1.014553708525258,9.128039162031719,0.21136245141014867,0.20491691825077635,0.9622169580201217,1.026607739704243,11.546603496241461,41.06430958816972
6,7,6,1.1458630268899013,13.355239238332201,3.309933484031582,-0.5492807499416801,1.0337321473545724,1.0296791486819454,12.404785768254868,41.18716594727782
7,7,7,1.1804877814618082,-21.131506839412427,1.7498543505975177,0.2679597094328362,1.0072582609566736,0.960309958586958,12.087099131480084,38.41239834347832
"""


@pytest.mark.parametrize("seed", [0, 7, 20261122, 2**63 - 1])
def test_draw_seed_is_the_spawned_child(seed):
    from tetherheli.studies.montecarlo import draw_seed

    children = np.random.SeedSequence(seed).spawn(40)
    for i in (0, 1, 17, 39):
        mine, child = draw_seed(seed, i), children[i]
        assert (mine.entropy, mine.spawn_key, mine.pool_size) == (
            child.entropy,
            child.spawn_key,
            child.pool_size,
        )
        np.testing.assert_array_equal(mine.generate_state(8), child.generate_state(8))
        a, b = np.random.default_rng(mine), np.random.default_rng(child)
        np.testing.assert_array_equal(a.standard_normal(5), b.standard_normal(5))


def test_results_equal_the_spawn_everything_code(short_file, tmp_path):
    """Seeds made per chunk give today's table: the dispersions equal those written when all N
    seeds were spawned up front, and every chunk's rows equal ``_run_chunk`` of the spawned
    children (the old code path)."""
    from tetherheli.studies.montecarlo.runner import _run_chunk

    _run(short_file, tmp_path / "a")
    lines = (tmp_path / "a" / "results.csv").read_text().splitlines()[1:]
    assert [",".join(r.split(",")[:11]) for r in lines[::2]] == SHORT_DRAWS_BEFORE.splitlines()
    base, config = load_montecarlo(short_file)
    children = np.random.SeedSequence(config.seed).spawn(config.runs)
    old = "".join(_run_chunk(base, config, children[lo : lo + 3], lo, 1, None) for lo in (0, 3, 6))
    assert "\n".join(lines) + "\n" == old


def test_ten_million_runs_start_in_bounded_memory(short_file, tmp_path):
    """No O(N) work before the first run: a 10^7-draw job allocates a few hundred kB before
    it would start its first chunk (spawning every seed took 4 GB)."""
    import tracemalloc

    base, config = load_montecarlo(short_file)
    huge = config.__class__(**{**config.__dict__, "runs": 10_000_000})
    # the nominal designs' check (O(1), before the draws) imports the design stack once
    from tetherheli.studies.montecarlo.runner import check_nominal_designs

    check_nominal_designs(base)
    tracemalloc.start()
    try:
        got = run_montecarlo(base, huge, tmp_path / "h", chunk_size=2, max_chunks=0)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert got is None and peak < 2_000_000
    assert not list((tmp_path / "h" / "partial").glob("chunk_*"))


# --- failed draws are data (issue 9, section 4) --------------------------------------------

#: A plant dispersed by +-50% in mass against a main-rotor thrust limit of 160 N: heavy draws
#: cannot hover (no trim within the actuator limits), tethered ones (25 N more) first.
FAILING = """
name = "mc_fail"
duration = 2.0
[actuators]
u_max = [160.0, 1e9, 1e9, 1e9]
[[wind]]
type = "pulse"
start = 0.5
duration = 0.5
magnitude = 20.0
direction = [1.0, 0.0, 0.0]
[montecarlo]
runs = 6
seed = 3
params = { "helicopter.m_F" = 50.0 }
"""


@pytest.fixture
def failing_file(tmp_path: Path) -> Path:
    p = tmp_path / "fail.toml"
    p.write_text(FAILING)
    return p


def test_a_draw_that_cannot_hover_is_a_failed_row(failing_file, tmp_path):
    from tetherheli.engine import loop as engine

    summary = _run(failing_file, tmp_path / "f")
    rows = _rows(tmp_path / "f")
    assert len(rows) == 12 and rows[0]["reason"] == ""
    failed = [r for r in rows if r["status"] != "0"]
    assert failed and len(failed) < len(rows)
    for r in failed:
        assert int(r["status"]) == engine.STATUS_SETUP
        assert r["message"] == engine.STATUS_MESSAGES[engine.STATUS_SETUP]
        assert "fMR3" in r["reason"] and "cannot hover" in r["reason"]
        assert math.isnan(float(r["peak_q1"])) and float(r["n_samples"]) == 0.0
    # the heavier the draw, the sooner it fails: some draws fly free but not tethered
    pairs = {(f["status"], t["status"]) for f, t in zip(rows[::2], rows[1::2], strict=True)}
    assert ("0", "6") in pairs and ("0", "0") in pairs
    # a failed run counts as +inf: in numpy's linear percentile a stand-in above every
    # completed value gives the same order; a percentile that reaches it is null
    for cfg in ("free", "tethered"):
        ok = [float(r["peak_q1"]) for r in rows if r["configuration"] == cfg and r["status"] == "0"]
        s = summary["statistics"][cfg]
        assert (s["runs"], s["completed"], s["failed"]) == (6, len(ok), 6 - len(ok))
        stand_in = np.array(ok + [1e6] * (6 - len(ok)))
        for p in (5, 25, 50, 75, 95):
            expected = float(np.percentile(stand_in, p))
            got = s["peak_q1"][f"p{p}"]
            assert got is None if expected > max(ok) else got == pytest.approx(expected, rel=1e-12)
        assert s["peak_q1"]["max"] == max(ok)
    assert summary["statistics"]["tethered"]["peak_q1"]["p95"] is None  # failures in the tail
    # the paired reduction: a draw whose tethered run failed is -inf (the bad tail)
    teth_only = sum(1 for f, t in zip(rows[::2], rows[1::2], strict=True)
                    if f["status"] == "0" and t["status"] != "0")  # fmt: skip
    assert summary["failed_draws"]["tethered_only"] == teth_only > 0
    assert summary["reduction_percent"]["peak_q1"]["p1"] is None


@pytest.mark.usefixtures("blank_figures")  # the chunks under test, not the plots
def test_cli_failed_draws_exit_0_or_1_with_strict(failing_file, tmp_path, capsys):
    from tetherheli import cli

    args = ["montecarlo", str(failing_file), "--out", str(tmp_path / "o"), "--quiet"]
    assert cli.main(args) == 0
    captured = capsys.readouterr()
    assert "failed (status, message and reason in" in captured.err
    assert "Traceback" not in captured.err and len(captured.err.strip().splitlines()) == 1
    assert cli.main([*args, "--strict"]) == 1  # the finished job, reread
    assert "failed (status, message and reason in" in capsys.readouterr().err
    # a job without failures is not affected by --strict
    assert cli.main([*args[:-2], str(tmp_path / "ok"), "--runs", "1", "--quiet", "--strict"]) == 0


# --- --max-chunks stops with its own exit code ---------------------------------------------


@pytest.mark.usefixtures("blank_figures")  # the chunks under test, not the plots
def test_cli_max_chunks_exit_3_then_resume(short_file, uninterrupted, tmp_path, capsys):
    from tetherheli import cli

    args = ["montecarlo", str(short_file), "--out", str(tmp_path / "o"), "--chunk-size", "3"]
    assert cli.main([*args, "--max-chunks", "1"]) == cli.EXIT_STOPPED == 3
    err = capsys.readouterr().err
    assert "--max-chunks" in err and "run the same command again to resume" in err
    assert not (tmp_path / "o" / "results.csv").exists()
    assert cli.main([*args, "--max-chunks", "5"]) == 0  # enough left to finish: a finished job
    assert (tmp_path / "o" / "results.csv").read_bytes() == uninterrupted


def test_cli_ten_million_runs_start_at_once(short_file, tmp_path, capsys):
    from tetherheli import cli

    out = tmp_path / "h"
    args = ["montecarlo", str(short_file), "--out", str(out), "--runs", "10000000"]
    assert cli.main([*args, "--chunk-size", "1", "--max-chunks", "1", "--quiet"]) == 3
    assert [p.name for p in sorted((out / "partial").glob("chunk_*"))] == [
        "chunk_000000000_000000001.csv"
    ]


# --- chunk files that can be trusted (issue 9, section 5) ----------------------------------


@pytest.mark.usefixtures("blank_figures")  # the chunks under test, not the plots
def test_damaged_chunks_are_named_and_computed_again(short_file, uninterrupted, tmp_path, capsys):
    """Truncated, empty, garbled, misplaced or old-format chunk files: each is named in one
    line on stderr and computed again; the table equals an uninterrupted run's."""
    full = uninterrupted
    out = tmp_path / "d"
    _run(short_file, out)
    assert (out / "results.csv").read_bytes() == full
    first = _chunks_of(out)[0].read_text()
    assert first.count("\n") == 7 and first.splitlines()[-1].startswith("# tetherheli")
    assert first.splitlines()[-1].split(",")[0] == "# tetherheli montecarlo chunk: draws 0..2"
    damages = {
        "truncated": lambda p: p.write_bytes(p.read_bytes()[:300]),
        "empty": lambda p: p.write_bytes(b""),
        "garbled": lambda p: p.write_text(p.read_text().replace(",free,", ",frXe,", 1)),
        "not UTF-8": lambda p: p.write_bytes(b"\xff\xfe" + p.read_bytes()),
        "old format": lambda p: p.write_text("".join(p.read_text().splitlines(True)[:-1])),
    }
    capsys.readouterr()
    for k, (what, damage) in enumerate(damages.items()):
        chunk = _chunks_of(out)[k % 3]
        damage(chunk)
        assert _run(short_file, out) is not None
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and str(chunk) in err[0] and "computing it again" in err[0], what
        assert (out / "results.csv").read_bytes() == full, what
    assert _run(short_file, out) is not None and capsys.readouterr().err == ""
    # a chunk holding other draws (copied over another)
    a, b, _ = _chunks_of(out)
    b.write_bytes(a.read_bytes())
    capsys.readouterr()
    _run(short_file, out)
    assert "holds draws 0..2, not 3..5" in capsys.readouterr().err
    assert (out / "results.csv").read_bytes() == full


@pytest.mark.usefixtures("blank_figures")  # the chunks under test, not the plots
def test_cli_truncated_chunk_is_recomputed(short_file, tmp_path, capsys):
    from tetherheli import cli

    out = tmp_path / "o"
    args = ["montecarlo", str(short_file), "--out", str(out), "--chunk-size", "3"]
    assert cli.main([*args, "--quiet"]) == 0
    whole = (out / "results.csv").read_bytes()
    chunk = _chunks_of(out)[1]
    chunk.write_bytes(chunk.read_bytes()[:-40])
    capsys.readouterr()
    assert cli.main(args) == 0
    err = capsys.readouterr().err
    lines = [line for line in err.replace("\r", "\n").splitlines() if "tetherheli" in line]
    assert lines == [f"tetherheli: {chunk} has no checksum line (truncated, or written before "
                     "checksums); computing it again"]  # fmt: skip
    assert (out / "results.csv").read_bytes() == whole


def test_cli_corrupt_job_file_names_it(short_file, tmp_path, capsys):
    from tetherheli import cli

    out = tmp_path / "o"
    args = ["montecarlo", str(short_file), "--out", str(out), "--quiet", "--runs", "2"]
    assert cli.main(args) == 0
    job = out / "partial" / "job.json"
    for content in (b"", b'{"scenario": ', b"\xff\xfe{}"):
        job.write_bytes(content)
        capsys.readouterr()
        assert cli.main(args) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and str(job) in err and "Traceback" not in err


def test_cli_non_utf8_scenario_and_params_name_their_path(tmp_path, capsys):
    from tetherheli import cli

    bad = tmp_path / "latin1.toml"
    bad.write_bytes(SHORT.replace('"mc_short"', '"caf\xe9"').encode("latin-1"))
    assert cli.main(["montecarlo", str(bad), "--out", str(tmp_path / "b")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and str(bad) in err and "UTF-8" in err
    assert cli.main(["trim", "--params", str(bad)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and str(bad) in err and "UTF-8" in err


# --- the progress line ----------------------------------------------------------------------


def test_interrupt_message_starts_a_new_line(short_file, tmp_path, capsys, monkeypatch):
    from tetherheli import cli
    from tetherheli.studies.montecarlo import runner

    real, calls = runner._run_chunk, []

    def interrupted(*args, **kwargs):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(runner, "_run_chunk", interrupted)
    out = tmp_path / "o"
    assert cli.main(["montecarlo", str(short_file), "--out", str(out), "--chunk-size", "3"]) == 130
    err = capsys.readouterr().err
    assert "3/8 draws" in err and "\ntetherheli: interrupted\n" in err
    assert len(_chunks_of(out)) == 1  # the finished chunk is kept


# --- Dask: a lost scheduler or no workers ---------------------------------------------------


@pytest.mark.usefixtures("blank_figures")  # the chunks under test, not the plots
def test_lost_scheduler_is_one_line_exit_1_and_resumable(
    short_file, uninterrupted, tmp_path, capsys, monkeypatch, local_cluster
):
    from tetherheli import cli
    from tetherheli.studies.montecarlo import runner

    cluster = local_cluster(n_workers=1, threads_per_worker=1, processes=False)
    real = runner._run_chunk

    def then_lose_the_scheduler(*args, **kwargs):
        rows = real(*args, **kwargs)
        cluster.close()
        return rows

    monkeypatch.setattr(runner, "_run_chunk", then_lose_the_scheduler)
    out = tmp_path / "o"
    args = ["montecarlo", str(short_file), "--out", str(out), "--chunk-size", "3"]
    try:
        code = cli.main(
            [*args, "--scheduler", cluster.scheduler_address, "--connect-timeout", "1", "--quiet"]
        )
    finally:
        cluster.close()
    err = capsys.readouterr().err
    assert code == 1 and len(err.strip().splitlines()) == 1, err
    assert "Dask scheduler" in err and "run the same command again to resume" in err
    assert len(_chunks_of(out)) == 1
    monkeypatch.setattr(runner, "_run_chunk", real)
    assert cli.main([*args, "--quiet"]) == 0
    assert (out / "results.csv").read_bytes() == uninterrupted


def test_no_workers_is_reported_after_the_timeout(short_file, tmp_path, capsys, local_cluster):
    from tetherheli import cli

    with local_cluster(n_workers=0, processes=False) as cluster:
        args = ["montecarlo", str(short_file), "--out", str(tmp_path / "o"), "--quiet"]
        code = cli.main(
            [*args, "--scheduler", cluster.scheduler_address, "--worker-timeout", "0.5"]
        )
    err = capsys.readouterr().err
    assert code == 1 and len(err.strip().splitlines()) == 1
    assert "no Dask worker" in err and "--worker-timeout" in err


IMPOSSIBLE_DRAWS = """
name = "mc_impossible"
duration = 0.5
[params.tension_control]
T_ref = 150.0
[montecarlo]
runs = 12
seed = 5
params = { "tether.K_C" = 50.0 }
"""


def test_a_draw_with_impossible_dispersed_values_is_a_failed_row(tmp_path, capsys):
    """A dispersed K_C below 2 T_ref / q9 (here 30 N/m, factor < 0.75) cannot give the
    reference tension: that draw's rows say so (status 6 with the reason) and the job goes on;
    --strict turns the failed rows into exit 1."""
    path = tmp_path / "mc.toml"
    path.write_text(IMPOSSIBLE_DRAWS)
    out = tmp_path / "out"
    assert main(["montecarlo", str(path), "--quiet", "--out", str(out)]) == 0
    rows = _rows(out)
    assert len(rows) == 24
    for r in rows:
        k_c = float(r["value:tether.K_C"])
        if k_c * 10.0 / 2.0 < 150.0:  # the most this tether gives at q9 = 10 m
            assert int(r["status"]) == Status.SETUP and "T_ref" in r["reason"]
            assert math.isnan(float(r["peak_q1"]))
        else:
            assert int(r["status"]) == Status.OK
    assert {int(r["status"]) for r in rows} == {int(Status.OK), int(Status.SETUP)}
    assert "failed" in capsys.readouterr().err
    assert main(["montecarlo", str(path), "--quiet", "--strict", "--out", str(out)]) == 1

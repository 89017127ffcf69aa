"""Scripts that write are commands too (issue 43, findings 1, 6 and 10): the examples, the
benchmarks and the docs' scripts write results by the commands' output rules
(``tetherheli._io``) and the project's pages by one rule (``cli._script.write_docs_file``);
every argument is checked before anything runs or is written, and a refusal is one line and
exit 2, never a traceback.

Each script's work is replaced here by a stub (``_no_work``: it fails the test if called) or
by a tiny one, so the output rules and the arguments are under test, quickly; the examples
run for real in ``tests/test_examples.py``."""

from __future__ import annotations

import importlib.util
import json
import os
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from tetherheli._io import OUTPUT_RECORD
from tetherheli.errors import ParameterError

ROOT = Path(__file__).resolve().parents[1]
FIGURE_EXAMPLES = {
    "paper_run_free_vs_tethered": "paper_sim1_q1.png",
    "python_control_dlqr_equals_lqi": "dlqr_lqi_poles.png",
    "sweep_reference_tension": "sweep_tref.png",
    "trim_and_linearization_poles": "trim_poles.png",
    "turbulence_to_dataframe": "turbulence_dataframe.png",
}


def _load(rel: str) -> ModuleType:
    """The script ``ROOT/rel`` as a module (its ``main`` not run)."""
    path = ROOT / rel
    spec = importlib.util.spec_from_file_location(f"script_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _no_work(*args, **kwargs):
    raise AssertionError("the script ran its work although it should have refused first")


def _tree(folder: Path) -> dict[str, tuple]:
    """Every entry below ``folder`` (links not followed): kind and bytes or target."""
    found = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            path = Path(root, name)
            rel = path.relative_to(folder).as_posix()
            if path.is_symlink():
                found[rel] = ("link", os.readlink(path))
            elif path.is_dir():
                found[rel] = ("dir",)
            else:
                found[rel] = ("file", path.read_bytes())
    return found


def _refused(code: int, err: str, *words: str) -> str:
    """A refusal: exit 2 and one line on stderr holding ``words``, no traceback."""
    lines = err.strip().splitlines()
    assert code == 2, err
    assert len(lines) == 1 and "Traceback" not in err, err
    for word in words:
        assert word in lines[0], lines[0]
    return lines[0]


def _planted(tmp_path: Path, out: Path, name: str) -> Path:
    """``out`` holding a link ``name`` to a file outside it; returns that file."""
    outside = tmp_path / "outside.txt"
    outside.write_text("the user's file\n")
    out.mkdir()
    (out / name).symlink_to(outside)
    return outside


# --- the examples that draw a figure --------------------------------------------------------


@pytest.fixture(scope="module")
def examples() -> dict[str, ModuleType]:
    pytest.importorskip("control")
    pytest.importorskip("pandas")
    return {name: _load(f"examples/{name}.py") for name in FIGURE_EXAMPLES}


def _blank() -> dict:
    from matplotlib.figure import Figure

    return Figure(figsize=(0.5, 0.5))


@pytest.mark.parametrize("name", sorted(FIGURE_EXAMPLES))
def test_an_example_never_writes_through_a_link_in_its_folder(
    examples, name, tmp_path, monkeypatch, capsys
):
    """Finding 1: a link planted where the figure goes is refused before any work, and the
    file it points to is kept (the example wrote through it before)."""
    module, figure = examples[name], FIGURE_EXAMPLES[name]
    monkeypatch.setattr(module, "figures", _no_work)
    out = tmp_path / "out"
    outside = _planted(tmp_path, out, figure)
    before = _tree(tmp_path)
    for extra in ([], ["--force"]):
        _refused(module.main([str(out), *extra]), capsys.readouterr().err, "OUT_DIR", figure)
    assert _tree(tmp_path) == before and outside.read_text() == "the user's file\n"


@pytest.mark.parametrize("name", sorted(FIGURE_EXAMPLES))
def test_an_example_refuses_a_file_a_foreign_folder_and_the_current_one(
    examples, name, tmp_path, monkeypatch, capsys
):
    module = examples[name]
    monkeypatch.setattr(module, "figures", _no_work)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a file").write_text("mine\n")
    (tmp_path / "theirs").mkdir()
    (tmp_path / "theirs" / "notes.txt").write_text("mine\n")
    before = _tree(tmp_path)
    for out, words in (
        (".", ("is the current directory",)),
        ("a file", ("is not a directory",)),
        ("a file/below", ("nothing can be created",)),
        ("theirs", ("was not created by tetherheli", "--force")),
    ):
        _refused(module.main([out]), capsys.readouterr().err, "OUT_DIR", *words)
    assert _tree(tmp_path) == before


def test_an_example_replaces_its_own_figure_and_keeps_everything_else(
    examples, tmp_path, monkeypatch, capsys
):
    """The default folder is a dedicated one; a re-run replaces the figure it wrote, keeps
    a user's file and another example's figure; an edited figure is the user's."""
    trim, paper = examples["trim_and_linearization_poles"], examples["paper_run_free_vs_tethered"]
    for module, figure in ((trim, "trim_poles.png"), (paper, "paper_sim1_q1.png")):
        monkeypatch.setattr(module, "figures", lambda figure=figure: {figure: _blank()})
    monkeypatch.chdir(tmp_path)
    assert trim.main([]) == 0 and paper.main([]) == 0
    out = tmp_path / "examples_out"
    (out / "notes.txt").write_text("mine\n")
    assert trim.main([]) == 0
    record = json.loads((out / OUTPUT_RECORD).read_text())["files"]
    assert record["trim_poles.png"]["writer"] == "trim_and_linearization_poles.py"
    assert record["paper_sim1_q1.png"]["writer"] == "paper_run_free_vs_tethered.py"
    assert (out / "notes.txt").read_text() == "mine\n"
    assert "wrote examples_out/trim_poles.png" in capsys.readouterr().out
    with open(out / "trim_poles.png", "ab") as fh:
        fh.write(b"edited")
    edited = (out / "trim_poles.png").read_bytes()
    _refused(trim.main([]), capsys.readouterr().err, "trim_poles.png", "was not written")
    assert (out / "trim_poles.png").read_bytes() == edited


# --- examples/train_residual.py -------------------------------------------------------------


@pytest.fixture(scope="module")
def residual() -> ModuleType:
    pytest.importorskip("gymnasium")
    return _load("examples/train_residual.py")


def _fake_evaluate(policy, seeds, task=None) -> dict:
    """``evaluate``'s figures without flying: returns that depend on the policy's action."""
    n = len(seeds)
    action = np.asarray(policy(np.ones((n, 13))), dtype=float).reshape(n, 4)
    total = -1.0 - np.abs(action).sum(axis=1) - 0.01 * np.arange(n)
    return {
        "return": total,
        "peak": 0.2 + 0.01 * np.arange(n),
        "rms": 0.1 + 0.01 * np.arange(n),
        "rms_force": np.abs(action[:, 0]),
        "failed": np.zeros(n, dtype=bool),
        "steps": np.full(n, 1000),
    }


@pytest.fixture
def tiny_training(residual, monkeypatch):
    """train_residual flown by ``_fake_evaluate`` (the output rules under test, not RL)."""
    monkeypatch.setattr(residual, "evaluate", _fake_evaluate)
    monkeypatch.setattr(residual, "lqi_feedback_gains", lambda *a, **k: np.zeros((4, 13)))
    monkeypatch.setattr(residual, "curve_figure", lambda *a, **k: _blank())
    return residual


TINY = ["--steps", "1", "--directions", "1", "--episodes", "1", "--curve-episodes", "2",
        "--test-episodes", "2"]  # fmt: skip


@pytest.mark.parametrize("name", ["residual_ars.json", "residual_ars_curve.png"])
def test_train_residual_never_writes_through_a_link_nor_over_a_foreign_file(
    residual, name, tmp_path, monkeypatch, capsys
):
    """Finding 1, as reported: a link planted in --out and an existing residual_* file are
    refused before training, with --force too, and both are kept."""
    monkeypatch.setattr(residual, "evaluate", _no_work)
    out = tmp_path / "out"
    outside = _planted(tmp_path, out, name)
    (out / "residual_ars_table.md").write_text("my table\n")
    before = _tree(tmp_path)
    for extra in ([], ["--force"]):
        code = residual.main([*TINY, "--out", str(out), *extra])
        _refused(code, capsys.readouterr().err, "train_residual.py: error: --out")
    assert _tree(tmp_path) == before and outside.read_text() == "the user's file\n"


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--n-envs", "1e8"], ["--n-envs = '1e8'", "[1, 1024]"]),
        (["--n-envs", "100000000"], ["--n-envs = '100000000'"]),
        (["--steps", "0"], ["--steps = '0'"]),
        (["--steps", "-3"], ["--steps = '-3'"]),
        (["--steps", "1e20"], ["--steps = '1e20'"]),
        (["--seed", "-1"], ["--seed = '-1'"]),
        (["--threads", "x"], ["--threads = 'x'"]),
        (["--curve-episodes", "0"], ["--curve-episodes = '0'"]),
        (["--test-episodes", "1"], ["--test-episodes = '1'"]),
        (["--eval-every", "0"], ["--eval-every = '0'"]),
        (["--directions", "1024", "--episodes", "1024"], ["--directions", "memory budget"]),
        (["--algo", "sac"], ["--algo"]),
    ],
)
def test_train_residual_refuses_bad_arguments_in_one_line(
    residual, args, words, tmp_path, monkeypatch, capsys
):
    """Finding 10: 0, negatives, huge values and non-numbers are one line, exit 2, before
    anything is allocated, run or written (``--n-envs 1e8`` was a traceback)."""
    monkeypatch.setattr(residual, "evaluate", _no_work)
    monkeypatch.chdir(tmp_path)
    code = residual.main([*TINY, *args, "--out", "out"])
    _refused(code, capsys.readouterr().err, *words)
    assert list(tmp_path.iterdir()) == []


def test_train_residual_refuses_bad_out_in_one_line(residual, tmp_path, monkeypatch, capsys):
    """Finding 10: --out a file, below a file, the current folder: one line, exit 2."""
    monkeypatch.setattr(residual, "evaluate", _no_work)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "f").write_text("mine\n")
    before = _tree(tmp_path)
    for out in ("f", "f/sub", ".", ""):
        _refused(residual.main([*TINY, "--out", out]), capsys.readouterr().err, "--out")
    assert _tree(tmp_path) == before


def test_train_residual_writes_its_outputs_whole_and_recorded(tiny_training, tmp_path, capsys):
    """A (stubbed) run writes every output at once with the record; a re-run replaces its
    own files and keeps a user's."""
    out = tmp_path / "out"
    assert tiny_training.main([*TINY, "--out", str(out)]) == 0
    names = tiny_training.output_names("ars")
    record = json.loads((out / OUTPUT_RECORD).read_text())["files"]
    assert sorted(record) == sorted(names)
    assert {e["writer"] for e in record.values()} == {"train_residual.py --algo ars"}
    assert np.load(out / "residual_ars_gains.npy").shape == (4, 13)
    assert json.loads((out / "residual_ars.json").read_text())["settings"]["steps"] == 1
    (out / "mine.txt").write_text("mine\n")
    assert tiny_training.main([*TINY, "--out", str(out)]) == 0
    assert (out / "mine.txt").read_text() == "mine\n"
    assert f"wrote {out / 'residual_ars.json'}" in capsys.readouterr().out


def _docs_root(tmp_path: Path, *pages: str) -> Path:
    """A scratch checkout holding copies of the repository's ``pages``."""
    root = tmp_path / "repo"
    for rel in pages:
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_bytes((ROOT / rel).read_bytes())
    for folder in ("img", "studies"):
        (root / "docs" / folder).mkdir(parents=True, exist_ok=True)
    return root


def test_train_residual_updates_the_docs_or_refuses_first(
    tiny_training, tmp_path, monkeypatch, capsys
):
    """--update-docs replaces the page's table and the figure (the project's own files);
    a link in their place is refused before training."""
    root = _docs_root(tmp_path, tiny_training.DOC_PAGE)
    monkeypatch.setattr(tiny_training, "ROOT", root)
    figure = root / "docs" / "img" / "residual_ars_curve.png"
    outside = tmp_path / "outside.png"
    outside.write_bytes(b"not ours")
    figure.symlink_to(outside)
    monkeypatch.setattr(tiny_training, "train_ars", _no_work)
    page = (root / tiny_training.DOC_PAGE).read_text()
    code = tiny_training.main([*TINY, "--out", str(tmp_path / "out"), "--update-docs"])
    _refused(code, capsys.readouterr().err, "docs/img/residual_ars_curve.png", "a link")
    assert outside.read_bytes() == b"not ours" and not (tmp_path / "out").exists()
    monkeypatch.undo()
    monkeypatch.setattr(tiny_training, "ROOT", root)
    monkeypatch.setattr(tiny_training, "evaluate", _fake_evaluate)
    monkeypatch.setattr(tiny_training, "lqi_feedback_gains", lambda *a, **k: np.zeros((4, 13)))
    monkeypatch.setattr(tiny_training, "curve_figure", lambda *a, **k: _blank())
    figure.unlink()
    code = tiny_training.main([*TINY, "--out", str(tmp_path / "out"), "--update-docs"])
    assert code == 0, capsys.readouterr().err
    new = (root / tiny_training.DOC_PAGE).read_text()
    assert new != page and "over 2 held-out episodes" in new
    assert figure.read_bytes() == (tmp_path / "out" / "residual_ars_curve.png").read_bytes()
    assert outside.read_bytes() == b"not ours"


# --- benchmarks/deck_study.py and the deck study --------------------------------------------


@pytest.fixture
def deck(monkeypatch, tmp_path):
    """benchmarks/deck_study.py over a scratch checkout, its study replaced by tiny rows."""
    from tetherheli.studies.deck import LandingRow, StationRow

    module = _load("benchmarks/deck_study.py")
    monkeypatch.setattr(module, "ROOT", _docs_root(tmp_path, module.PAGE))
    station = StationRow(0.5, "tethered", "perfect", False, 0.1, 0.2, 0.3, 20.0, 30.0, 1, 0)
    landing = LandingRow(0.5, True, 1, 1, 0.3, 0.3, 0.1, 0.05, {})
    monkeypatch.setattr(module, "station_rows", lambda *a, **k: [station])
    monkeypatch.setattr(module, "landing_rows", lambda *a, **k: [landing])
    return module


@pytest.mark.parametrize("seeds", ["0", "-1", "abc", "1e3", "2.5", "101", "10000000000"])
def test_deck_study_refuses_nonsense_seeds_before_anything(deck, seeds, monkeypatch, capsys):
    """Finding 6: ``--seeds 0`` rewrote the page with 0/0 tables, exit 0; now every value
    outside [1, MAX_SEEDS] is one line, exit 2, nothing flown or written."""
    monkeypatch.setattr(deck, "station_rows", _no_work)
    monkeypatch.setattr(deck, "landing_rows", _no_work)
    page = (deck.ROOT / deck.PAGE).read_bytes()
    for args in (["--seeds", seeds], ["--seeds", seeds, "--print"]):
        _refused(deck.main(args), capsys.readouterr().err, f"--seeds = '{seeds}'", "[1, 100]")
    assert (deck.ROOT / deck.PAGE).read_bytes() == page


def test_deck_study_writes_the_page_whole(deck, capsys):
    assert deck.main(["--seeds", "1"]) == 0
    text = (deck.ROOT / deck.PAGE).read_text()
    assert "| 0.5 | tethered | perfect | no |" in text and "| 0.5 | yes | 1/1 |" in text
    assert "--seeds 1`" in text and f"wrote {deck.PAGE}" in capsys.readouterr().out


def test_deck_study_refuses_a_linked_page_before_flying(deck, tmp_path, monkeypatch, capsys):
    """The page is the project's: a link in its place (or on the way) is never written
    through."""
    monkeypatch.setattr(deck, "station_rows", _no_work)
    page = deck.ROOT / deck.PAGE
    outside = tmp_path / "outside.md"
    outside.write_text("mine\n")
    page.unlink()
    page.symlink_to(outside)
    _refused(deck.main(["--seeds", "1"]), capsys.readouterr().err, deck.PAGE, "a link")
    assert outside.read_text() == "mine\n" and page.is_symlink()


def test_deck_study_with_nothing_to_report_writes_nothing(deck, monkeypatch, capsys):
    monkeypatch.setattr(deck, "landing_rows", lambda *a, **k: [])
    page = (deck.ROOT / deck.PAGE).read_bytes()
    assert deck.main(["--seeds", "1"]) == 70  # a study without rows is a bug, not a page
    assert "nothing to report" in capsys.readouterr().err
    assert (deck.ROOT / deck.PAGE).read_bytes() == page


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"seeds": ()}, "seeds"),
        ({"seeds": range(0)}, "seeds"),
        ({"seeds": [-1]}, "seeds"),
        ({"seeds": [0.5]}, "seeds"),
        ({"seeds": range(10**12)}, "seeds"),
        ({"heights": (25.0,)}, "heights"),
        ({"heights": ()}, "heights"),
        ({"heights": "abc"}, "heights"),
        ({"sensings": ("sonar",)}, "sensings"),
        ({"configurations": ("boat",)}, "configurations"),
        ({"feedforwards": (1,)}, "feedforwards"),
    ],
)
def test_deck_rows_refuse_empty_or_unknown_arguments(kwargs, field):
    """Finding 10: the study raised KeyError (an unknown sensing) or ZeroDivisionError (no
    seeds: ``success_rate``); each argument is now checked, one line naming it."""
    from tetherheli.studies.deck import landing_rows, station_rows

    grid = {"heights": (0.5,), "seeds": (0,), **kwargs}
    with pytest.raises(ParameterError, match=f"^{field} = "):
        station_rows(grid["heights"], grid["seeds"], **{
            k: v for k, v in kwargs.items() if k not in ("heights", "seeds")})  # fmt: skip
    if field in ("heights", "seeds", "feedforwards"):
        with pytest.raises(ParameterError, match=f"^{field} = "):
            landing_rows(grid["heights"], grid["seeds"], **{
                k: v for k, v in kwargs.items() if k == "feedforwards"})  # fmt: skip


# --- the docs rule and the other docs scripts -----------------------------------------------


def test_the_docs_rule_replaces_a_page_whole_and_never_through_a_link(tmp_path):
    from tetherheli._io import OutputPathError
    from tetherheli.cli._script import write_docs_file

    root = tmp_path / "repo"
    (root / "docs" / "studies").mkdir(parents=True)
    page = root / "docs" / "studies" / "p.md"
    page.write_text("old\n")
    write_docs_file(root, "docs/studies/p.md", "new\n")
    assert page.read_text() == "new\n" and sorted(os.listdir(page.parent)) == ["p.md"]
    outside = tmp_path / "outside"
    (outside / "studies").mkdir(parents=True)
    (outside / "studies" / "p.md").write_text("theirs\n")
    (outside / "x").symlink_to(outside / "studies")
    cases = {
        "a link at the page": lambda: (
            page.unlink(),
            page.symlink_to(outside / "studies" / "p.md"),
        ),
        "a link on the way": lambda: (
            os.rename(root / "docs" / "studies", tmp_path / "moved"),
            (root / "docs" / "studies").symlink_to(outside / "studies"),
        ),
        "a file on the way": lambda: (
            os.unlink(root / "docs" / "studies"),
            (root / "docs" / "studies").write_text("a file\n"),
        ),
    }
    for what, make in cases.items():
        make()
        before = _tree(tmp_path)
        with pytest.raises(OutputPathError, match="docs/studies"):
            write_docs_file(root, "docs/studies/p.md", "written through\n")
        assert _tree(tmp_path) == before, what
    with pytest.raises(OutputPathError, match="does not exist"):
        write_docs_file(root, "docs/new/p.md", "x")
    assert (outside / "studies" / "p.md").read_text() == "theirs\n"


def test_gen_scenario_reference_and_moordyn_use_the_docs_rule(tmp_path, monkeypatch, capsys):
    pytest.importorskip("scipy")
    from tetherheli.scenario.reference import scenario_reference

    gen = _load("docs/gen_scenario_reference.py")
    root = _docs_root(tmp_path, gen.PAGE)
    monkeypatch.setattr(gen, "ROOT", root)
    (root / gen.PAGE).write_text("stale\n")
    assert gen.main([]) == 0
    assert (root / gen.PAGE).read_text() == scenario_reference()
    monkeypatch.syspath_prepend(str(ROOT / "benchmarks"))  # its sibling moordyn_cases
    moordyn = _load("benchmarks/moordyn_validation.py")
    monkeypatch.setattr(moordyn, "ROOT", root)
    monkeypatch.setattr(moordyn, "page", _no_work)
    (root / moordyn.PAGE).symlink_to(tmp_path / "elsewhere.md")
    _refused(moordyn.main([]), capsys.readouterr().err, moordyn.PAGE, "a link")
    assert not (tmp_path / "elsewhere.md").exists()


def test_regenerate_tables_figures_follow_one_rule(tmp_path, monkeypatch, capsys):
    """--figures into the checkout's docs: the docs rule (a link refused before any table);
    elsewhere: an output directory by the commands' rules."""
    regen = _load("docs/regenerate_tables.py")
    root = _docs_root(tmp_path)
    monkeypatch.setattr(regen, "ROOT", root)
    (root / "docs" / "img" / "release.png").symlink_to(tmp_path / "elsewhere.png")
    monkeypatch.setitem(regen.TABLES, "release", (_no_work, False))
    figures = str(root / "docs" / "img")
    code = regen.main(["--only", "release", "--figures", figures])
    _refused(code, capsys.readouterr().err, "docs/img/release.png", "a link")

    def table(work: Path, staged: Path | None) -> None:
        (staged / "release.png").write_bytes(b"png")

    monkeypatch.setitem(regen.TABLES, "release", (table, False))
    (root / "docs" / "img" / "release.png").unlink()
    assert regen.main(["--only", "release", "--figures", figures]) == 0
    assert (root / "docs" / "img" / "release.png").read_bytes() == b"png"
    out = tmp_path / "figs"
    assert regen.main(["--only", "release", "--figures", str(out)]) == 0
    assert json.loads((out / OUTPUT_RECORD).read_text())["files"]["release.png"]
    (tmp_path / "theirs").mkdir()
    (tmp_path / "theirs" / "release.png").write_bytes(b"theirs")
    for extra in ([], ["--force"]):
        code = regen.main(["--only", "release", "--figures", str(tmp_path / "theirs"), *extra])
        _refused(code, capsys.readouterr().err, "--figures")
    assert (tmp_path / "theirs" / "release.png").read_bytes() == b"theirs"


# --- benchmarks/bench_mpc.py --pareto and benchmarks/issue24_figures.py --json ---------------


@pytest.fixture(scope="module")
def bench_mpc() -> ModuleType:
    pytest.importorskip("osqp")
    sys.path.insert(0, str(ROOT / "benchmarks"))  # it imports its sibling tune_tether_lqi
    try:
        return _load("benchmarks/bench_mpc.py")
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))


def _pareto_csv(bench_mpc, folder: Path, monkeypatch) -> Path:
    import tetherheli.viz.plots as plots

    monkeypatch.setattr(plots, "figure_pareto", lambda *a, **k: _figure_with_axes())
    rows = [
        {c: (True if c in ("completed", "admissible") else float(i + j))
         for j, c in enumerate(bench_mpc.PARETO_COLUMNS)}
        for i in range(3)
    ]  # fmt: skip
    bench_mpc.write_pareto(str(folder), rows, {"paper": (1.0, 40.0)})
    return folder / "mpc_pareto.csv"


def _figure_with_axes():
    fig = _blank()
    fig.add_subplot()
    return fig


def test_bench_mpc_pareto_claims_its_folder_first_and_reads_csv_safely(
    bench_mpc, tmp_path, monkeypatch, capsys
):
    written = _pareto_csv(bench_mpc, tmp_path / "a", monkeypatch)
    capsys.readouterr()
    out = tmp_path / "b"
    assert bench_mpc.main(["--pareto", str(out), "--pareto-csv", str(written)]) == 0
    assert sorted(json.loads((out / OUTPUT_RECORD).read_text())["files"]) == sorted(
        bench_mpc.PARETO_FILES
    )
    assert (out / "mpc_pareto.csv").read_bytes() == written.read_bytes()
    outside = _planted(tmp_path, tmp_path / "c", "mpc_pareto.md")
    for extra in ([], ["--force"]):
        code = bench_mpc.main(["--pareto", str(tmp_path / "c"), "--pareto-csv", str(written),
                               *extra])  # fmt: skip
        _refused(code, capsys.readouterr().err, "--pareto", "mpc_pareto.md")
    assert outside.read_text() == "the user's file\n"
    secret = tmp_path / "secret.csv"
    secret.write_text("T_ref,token\n1,s3cr3t-t0ken\n")
    code = bench_mpc.main(["--pareto", str(tmp_path / "d"), "--pareto-csv", str(secret)])
    line = _refused(code, capsys.readouterr().err, "--pareto-csv")
    assert "s3cr3t" not in line and not (tmp_path / "d").exists()
    for args, word in (
        (["--tune", "-1"], "--tune"),
        (["--start", "1,2"], "--start"),
        (["--tension", "nan"], "--tension"),
        (["--robust", "0"], "--robust"),
    ):
        _refused(bench_mpc.main(args), capsys.readouterr().err, word)  # fmt: skip


def test_issue24_json_is_a_new_file_or_its_own(tmp_path, monkeypatch, capsys):
    figures = _load("benchmarks/issue24_figures.py")
    monkeypatch.setattr(figures, "bench_ab", _no_work)
    theirs = tmp_path / "table.json"
    theirs.write_text("{}\n")
    base = ["--baseline", str(ROOT / "src")]
    _refused(figures.main([*base, "--json", str(theirs)]), capsys.readouterr().err, "--json")
    _refused(figures.main([*base, "--rounds", "0"]), capsys.readouterr().err, "--rounds")
    _refused(figures.main(["--baseline", str(tmp_path)]), capsys.readouterr().err, "--baseline")
    assert theirs.read_text() == "{}\n"

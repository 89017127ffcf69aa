# not-for-ci: trains for minutes, needs the `rl` extra (tests/test_residual_policy.py runs it tiny)
"""Train a residual policy on top of the paper's controller that beats the paper's controller.

The task is the shipped environment, ``tetherheli/TetheredHover-v0`` (``TASK``): the paper's
tethered helicopter hovering at its trim, flown by the paper's LQI with integral action and
tether-torque feed-forward (eqs 50-56) exactly as ``simulate`` flies it; per episode a wind
drawn among a pulse, a sine and turbulence (up to 20 N, up to 3 m/s mean wind); reward
``-(|q_1..3 - q_ref|^2 + 0.01 |a|^2)`` per 10 ms step. The only change from the registered
defaults is the episode length, 10 s instead of 30 s. The action is added to the paper
controller's command (``residual=True``), so the zero action *is* the paper's controller.

Two trainers (``--algo``):

- ``ars`` (default): a linear residual a = clip(W obs / OBS_SCALE) trained by augmented
  random search (``train_ars``) in the compiled vector environment, every candidate of an
  iteration flown on the same training winds (common random numbers);
- ``ppo``: Stable-Baselines3 PPO with an MLP policy on ``TetheredHoverSB3VecEnv``
  (``train_ppo``; observations and rewards normalised by ``VecNormalize``, small initial
  action noise). Within minutes it does not beat the zero action (see the docs page).

Everything is seeded (``--seed``; the winds by seed ranges that never overlap). The learning
curve flies the current policy (deterministic) on the curve's seeds; at the end the policy
and the zero action fly the same held-out test seeds (``--test-episodes``). Written into
``--out`` whole at the end, by the commands' output rules (``tetherheli._io``: the folder is
checked before training; a link, a foreign file or a changed one where an output goes is
refused, never written through or replaced; ``--force`` writes beside foreign files), ALGO
``ars`` or ``ppo``:

- ``residual_ALGO_curve.png``: mean episode return on the curve's seeds against training
  steps, with the zero action's mean return on the same seeds as a line;
- ``residual_ALGO_table.md``: return (mean +- std), peak and RMS position deviation, the
  residual's RMS main-rotor force and the failures of both on the test seeds, with the
  paired difference;
- ``residual_ALGO.json``: the same figures, the curve and the run's settings; the gains
  (``residual_ars_gains.npy``) or the PPO model and its normalisation.

``--update-docs`` also copies the figure to ``docs/img`` and the table into
``docs/studies/residual_policy.md`` (between its markers; the project's own files, replaced
whole by ``cli._script.write_docs_file``). Every argument is checked before anything runs
(one line, exit 2), the environment copies against the memory budget too. ``--algo ppo``
needs ``pip install "tetherheli[rl]"`` (ARS only Gymnasium). Example (a few minutes on two
shared cores)::

    python examples/train_residual.py --out residual_out --update-docs
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from tetherheli.cli._common import count_arg
from tetherheli.cli._script import (
    claim,
    docs_file,
    out_argument,
    run_script,
    script_parser,
    write_docs_file,
)
from tetherheli.errors import TetherheliError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

ROOT = Path(__file__).resolve().parents[1]
#: The docs page and the figures' folder ``--update-docs`` writes (relative to ``ROOT``).
DOC_PAGE = "docs/studies/residual_policy.md"
DOC_IMG = "docs/img"

#: The task: the registered environment's defaults (paper's controller, pulse/sine/turbulence
#: winds, reward -(|e|^2 + 0.01 |a|^2)) with 10 s episodes.
TASK: dict[str, Any] = {"max_episode_time": 10.0}

#: Seed bases: PPO's training copies use seed, seed + 1, ... (ARS: ``TRAIN_SEED``); the curve
#: and the test use their own ranges, far from any training seed.
CURVE_SEED = 1_000_000
TEST_SEED = 2_000_000

#: PPO's settings: small initial action noise (std e^-2 of the unit action, 2.7 N on the
#: collective) so that exploration starts near the paper's controller.
PPO_SETTINGS: dict[str, Any] = {
    "n_steps": 128,
    "batch_size": 1024,
    "n_epochs": 10,
    "learning_rate": 3e-4,
    "gamma": 0.99,
    "gae_lambda": 0.95,
    "clip_range": 0.2,
    "policy_kwargs": {"net_arch": [64, 64], "log_std_init": -2.0},
}

Policy = Callable[[np.ndarray], np.ndarray]


def zero_policy(obs: np.ndarray) -> np.ndarray:
    """The zero residual: the paper's controller alone.

    Parameters
    ----------
    obs : ndarray, shape (n, 13)
        Observations of n copies.

    Returns
    -------
    ndarray, shape (n, 4), float32
        Zeros.
    """
    return np.zeros((obs.shape[0], 4), dtype=np.float32)


def evaluate(policy: Policy, seeds: Sequence[int], task: dict[str, Any] | None = None) -> dict:
    """Fly one episode per seed with ``policy`` (all at once in the vector environment).

    Parameters
    ----------
    policy : callable
        Maps the observations (n, 13) to actions (n, 4).
    seeds : sequence of int
        One episode per seed (copy i is reset with ``seeds[i]``, as a single environment
        reset with that seed).
    task : dict, optional
        Keyword arguments of the environment (default ``TASK``).

    Returns
    -------
    dict
        Per episode (arrays of len(seeds)): ``return`` (the sum of rewards), ``peak`` and
        ``rms`` of the position deviation |q_1..3 - q_ref| [m] over the episode's samples,
        ``rms_force`` the RMS residual on the main-rotor force [N], ``failed`` (bool) and
        ``steps``.
    """
    from tetherheli.envs.vector import TetheredHoverVectorEnv

    task = TASK if task is None else task
    n = len(seeds)
    venv = TetheredHoverVectorEnv(n, **task)
    scale = venv.env.action_scale
    y_ref = venv.env.trim.y[:3]
    obs, _ = venv.reset(seed=[int(s) for s in seeds])
    alive = np.ones(n, dtype=bool)
    total, peak, sq, force_sq = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    steps, failed = np.zeros(n, dtype=int), np.zeros(n, dtype=bool)
    for _ in range(venv.env.n_max):
        action = np.asarray(policy(obs), dtype=np.float32).reshape(n, 4)
        force = scale[0] * np.clip(action[:, 0], -1.0, 1.0)
        obs, reward, terminated, truncated, info = venv.step(action)
        error = np.linalg.norm(info["outputs"][:, :3] - y_ref, axis=1)
        total += np.where(alive, reward, 0.0)
        peak = np.where(alive, np.maximum(peak, np.nan_to_num(error, nan=np.inf)), peak)
        sq += np.where(alive, np.nan_to_num(error, nan=np.inf) ** 2, 0.0)
        force_sq += np.where(alive, force**2, 0.0)
        steps += alive
        failed |= alive & terminated
        alive &= ~(terminated | truncated)
        if not alive.any():
            break
    venv.close()
    return {
        "return": total,
        "peak": peak,
        "rms": np.sqrt(sq / steps),
        "rms_force": np.sqrt(force_sq / steps),
        "failed": failed,
        "steps": steps,
    }


#: Physical scale of each observation entry (order ``OBSERVATION_NAMES``): 0.2 m, 0.05 rad,
#: 0.2 m/s, 0.2 rad/s, 5 N. The linear policy acts on observation / OBS_SCALE.
OBS_SCALE = np.array([0.2] * 3 + [0.05] * 3 + [0.2] * 6 + [5.0])

#: ARS's settings: directions per iteration, episodes per candidate (the same seeds for all
#: candidates of an iteration), exploration radius, step size, best directions kept.
ARS_SETTINGS: dict[str, Any] = {
    "directions": 16,
    "episodes": 8,
    "radius": 0.02,
    "step_size": 0.01,
    "top": 8,
}

#: Seed base of ARS's training episodes (iteration j uses TRAIN_SEED + j * episodes + ...).
TRAIN_SEED = 3_000_000


def linear_policy(gains: np.ndarray) -> Policy:
    """The linear residual a = clip(W (obs / OBS_SCALE), -1, 1), one W per copy or shared.

    Parameters
    ----------
    gains : ndarray, shape (4, 13) or (n, 4, 13)
        W, in unit action per unit of scaled observation; (n, 4, 13) gives copy i its own.

    Returns
    -------
    callable
        Observations (n, 13) to actions (n, 4), float32.
    """
    gains = np.asarray(gains, dtype=float)

    def act(obs: np.ndarray) -> np.ndarray:
        scaled = np.asarray(obs, dtype=float) / OBS_SCALE
        if gains.ndim == 2:
            a = scaled @ gains.T
        else:
            a = np.einsum("nij,nj->ni", gains, scaled)
        return np.clip(a, -1.0, 1.0).astype(np.float32)

    return act


def lqi_feedback_gains(alpha: float = 1.0, task: dict[str, Any] | None = None) -> np.ndarray:
    """W of the hand-made residual that adds alpha times the paper LQI's own state feedback.

    The LQI commands u = u0 - Kx (x - x0) - Kz z (eq 54). The residual a = -alpha Kx dx /
    action_scale makes the state feedback (1 + alpha) Kx and leaves the integral action as
    it is. The observation gives dx: the angles and rates directly, q7..q9 from the position
    deviation through the output map's Jacobian at the trim (eqs 43-45, central differences).

    Parameters
    ----------
    alpha : float, optional
        Added fraction of the LQI's state feedback (default 1: doubled).
    task : dict, optional
        Keyword arguments of the environment (default ``TASK``).

    Returns
    -------
    ndarray, shape (4, 13)
        W for :func:`linear_policy` (unit action per unit of scaled observation).
    """
    from tetherheli.envs.env import TetheredHoverEnv
    from tetherheli.model.kernels import tethered_outputs
    from tetherheli.runs.setup import run_setup

    env = TetheredHoverEnv(**(TASK if task is None else task))
    model, trim, gain, _, _ = run_setup(env.scenario)
    c = np.ascontiguousarray(model.constants)
    kx = np.asarray(gain.K)[:, :12]
    jac, h = np.empty((3, 6)), 1e-6
    for j in range(6):
        up, down, y_up, y_down = trim.x.copy(), trim.x.copy(), np.empty(4), np.empty(4)
        up[j] += h
        down[j] -= h
        tethered_outputs(up, c, y_up)
        tethered_outputs(down, c, y_down)
        jac[:, j] = (y_up[:3] - y_down[:3]) / (2 * h)
    inv = np.linalg.inv(jac[:, 3:6])
    state_from_obs = np.zeros((12, len(OBS_SCALE)))  # dx (q4..q9, u1..u6) = M obs
    state_from_obs[0:3, 3:6] = np.eye(3)
    state_from_obs[3:6, 0:3] = inv
    state_from_obs[3:6, 3:6] = -inv @ jac[:, 0:3]
    state_from_obs[6:12, 6:12] = np.eye(6)
    return -alpha * (kx @ state_from_obs) * OBS_SCALE / env.action_scale[:, None]


def train_ars(
    steps: int,
    seed: int = 0,
    eval_every: int = 1,
    curve_episodes: int = 20,
    task: dict[str, Any] | None = None,
    log: Callable[[str], None] = print,
    ars: dict[str, Any] | None = None,
) -> tuple[np.ndarray, list[tuple[int, float]], float]:
    """Train the linear residual by augmented random search (ARS, Mania et al. 2018, V1-t).

    Each iteration draws ``directions`` Gaussian perturbations d_k of W, flies W + nu d_k
    and W - nu d_k on the same ``episodes`` fresh training seeds (common random numbers:
    the candidates of an iteration meet the same winds, so their difference is the policy's
    and not the wind's), and steps W along the ``top`` best directions, scaled by the
    standard deviation of their returns.

    Parameters
    ----------
    steps : int
        Training steps (10 ms samples summed over all copies), >= 1; the last iteration may
        pass it.
    seed : int, optional
        Seed of the directions; the training winds are seeded by ``TRAIN_SEED`` onwards.
    eval_every : int, optional
        Iterations between two points of the learning curve (default 1).
    curve_episodes : int, optional
        Episodes per curve point, on seeds ``CURVE_SEED + i`` (default 20).
    task : dict, optional
        Keyword arguments of the environment (default ``TASK``).
    log : callable, optional
        Receives one line per curve point.
    ars : dict, optional
        Settings that replace those of ``ARS_SETTINGS``.

    Returns
    -------
    gains : ndarray, shape (4, 13)
        The W of the best curve point (the curve's seeds are disjoint from the test's).
    curve : list of (int, float)
        (training steps, mean return of W on the curve's seeds), from step 0.
    seconds : float
        Wall-clock time of the training, curve evaluations included [s].
    """
    settings = {**ARS_SETTINGS, **(ars or {})}
    n_dir, n_ep, nu = settings["directions"], settings["episodes"], settings["radius"]
    top = min(settings["top"], n_dir)
    rng = np.random.default_rng(seed)
    curve_seeds = [CURVE_SEED + i for i in range(curve_episodes)]
    gains = np.zeros((4, len(OBS_SCALE)))
    best, curve, done, iteration = (-math.inf, gains), [], 0, 0
    start = time.perf_counter()

    def point() -> None:
        nonlocal best
        mean = float(np.mean(evaluate(linear_policy(gains), curve_seeds, task)["return"]))
        curve.append((done, mean))
        if mean > best[0]:
            best = (mean, gains.copy())
        log(f"  step {done:>11,d}: mean return {mean:10.3f}")

    point()
    while done < steps:
        d = rng.standard_normal((n_dir, *gains.shape))
        candidates = np.repeat(np.concatenate([gains + nu * d, gains - nu * d]), n_ep, axis=0)
        seeds = [TRAIN_SEED + iteration * n_ep + j for j in range(n_ep)] * (2 * n_dir)
        result = evaluate(linear_policy(candidates), seeds, task)
        done += int(result["steps"].sum())
        returns = result["return"].reshape(2 * n_dir, n_ep).mean(axis=1)
        plus, minus = returns[:n_dir], returns[n_dir:]
        keep = np.argsort(-np.maximum(plus, minus))[:top]
        sigma = float(np.std(np.concatenate([plus[keep], minus[keep]]))) or 1.0
        step = np.einsum("k,kij->ij", plus[keep] - minus[keep], d[keep])
        gains = gains + settings["step_size"] / (top * sigma) * step
        iteration += 1
        if iteration % eval_every == 0 or done >= steps:
            point()
    return best[1], curve, time.perf_counter() - start


def sb3_policy(model: Any, normalize: Any) -> Policy:
    """The trained policy's deterministic action on raw observations.

    Parameters
    ----------
    model : stable_baselines3.PPO
        The trained model.
    normalize : stable_baselines3.common.vec_env.VecNormalize
        The training environment's observation normalisation (its statistics are used as
        they are, not updated).

    Returns
    -------
    callable
        Observations (n, 13) to actions (n, 4).
    """

    def act(obs: np.ndarray) -> np.ndarray:
        action, _ = model.predict(normalize.normalize_obs(obs), deterministic=True)
        return action

    return act


def train_ppo(
    steps: int,
    seed: int = 0,
    n_envs: int = 32,
    eval_every: int = 20_000,
    curve_episodes: int = 20,
    task: dict[str, Any] | None = None,
    log: Callable[[str], None] = print,
    ppo: dict[str, Any] | None = None,
) -> tuple[Any, Any, list[tuple[int, float]], float]:
    """Train PPO on the residual for ``steps`` environment steps.

    Parameters
    ----------
    steps : int
        Training steps (summed over the copies), >= 1; PPO rounds up to whole rollouts of
        ``n_envs`` x 128 steps.
    seed : int, optional
        Seed of PyTorch, NumPy and the training copies (copy i: seed + i).
    n_envs : int, optional
        Environment copies (default 32).
    eval_every : int, optional
        Steps between two points of the learning curve (default 20,000).
    curve_episodes : int, optional
        Episodes per point of the learning curve, on seeds ``CURVE_SEED + i`` (default 20).
    task : dict, optional
        Keyword arguments of the environment (default ``TASK``).
    log : callable, optional
        Receives one line per curve point.
    ppo : dict, optional
        Settings of ``stable_baselines3.PPO`` that replace those of ``PPO_SETTINGS``.

    Returns
    -------
    model : stable_baselines3.PPO
        The trained model.
    normalize : VecNormalize
        Its observation normalisation.
    curve : list of (int, float)
        (training steps, mean deterministic return on the curve's seeds), from step 0.
    seconds : float
        Wall-clock time of the training, curve evaluations included [s].
    """
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecMonitor, VecNormalize

    from tetherheli.envs.sb3 import TetheredHoverSB3VecEnv

    task = TASK if task is None else task
    torch.manual_seed(seed)
    env = TetheredHoverSB3VecEnv(n_envs, **task)
    env.seed(seed)
    settings = {**PPO_SETTINGS, **(ppo or {})}
    # whole mini-batches of a rollout (n_steps x n_envs)
    settings["batch_size"] = min(settings["batch_size"], settings["n_steps"] * n_envs)
    normalize = VecNormalize(
        VecMonitor(env), norm_obs=True, norm_reward=True, gamma=settings["gamma"]
    )
    model = PPO("MlpPolicy", normalize, seed=seed, device="cpu", verbose=0, **settings)
    curve_seeds = [CURVE_SEED + i for i in range(curve_episodes)]
    curve: list[tuple[int, float]] = []

    def point() -> None:
        mean = float(np.mean(evaluate(sb3_policy(model, normalize), curve_seeds, task)["return"]))
        curve.append((int(model.num_timesteps), mean))
        log(f"  step {model.num_timesteps:>9,d}: mean return {mean:10.3f}")

    class Curve(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.next = eval_every

        def _on_step(self) -> bool:
            if self.num_timesteps >= self.next:
                point()
                self.next += eval_every
            return True

    start = time.perf_counter()
    point()
    model.learn(total_timesteps=steps, callback=Curve())
    if curve[-1][0] != model.num_timesteps:
        point()
    return model, normalize, curve, time.perf_counter() - start


def summary(runs: dict[str, dict]) -> dict:
    """Mean and standard deviation of each per-episode figure, and the paired difference of
    the returns (policy minus zero action).

    Parameters
    ----------
    runs : dict
        ``{name: evaluate(...)}`` on the same seeds, with ``"zero action"`` and ``"policy"``
        among the names.

    Returns
    -------
    dict
        Per run: ``{figure: [mean, std]}`` and ``failures``; ``paired``: mean and standard
        error of the return difference and the number of episodes the policy did better.
    """
    out: dict[str, Any] = {}
    for name, run in runs.items():
        out[name] = {
            key: [float(np.mean(run[key])), float(np.std(run[key], ddof=1))]
            for key in ("return", "peak", "rms", "rms_force")
        }
        out[name]["failures"] = int(np.sum(run["failed"]))
    diff = runs["policy"]["return"] - runs["zero action"]["return"]
    n = len(diff)
    out["paired"] = {
        "mean": float(np.mean(diff)),
        "stderr": float(np.std(diff, ddof=1) / math.sqrt(n)),
        "better": int(np.sum(diff > 0)),
        "episodes": n,
    }
    return out


def table(figures: dict, command: str, labels: dict[str, str]) -> str:
    """The Markdown table of :func:`summary`'s figures.

    Parameters
    ----------
    figures : dict
        :func:`summary`'s result.
    command : str
        The command that made it (printed under the table).
    labels : dict
        Row label of each run of ``figures`` (in the rows' order).

    Returns
    -------
    str
        The table and a line with the paired difference and the command.
    """
    lines = [
        "| controller | return | peak deviation [m] | RMS deviation [m] "
        "| RMS residual fMR3 [N] | failures |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for name, row in labels.items():
        f = figures[name]
        cells = [f"{f[k][0]:.3f} +- {f[k][1]:.3f}" for k in ("return", "peak", "rms")]
        cells.append(f"{f['rms_force'][0]:.2f}")
        lines.append(f"| {row} | {' | '.join(cells)} | {f['failures']} |")
    p = figures["paired"]
    lines += [
        "",
        f"Mean +- standard deviation over {p['episodes']} held-out episodes (the same seeds for "
        f"all). Paired return difference, policy minus zero action: {p['mean']:+.3f} +- "
        f"{p['stderr']:.3f} (standard error); the policy did better in {p['better']} of "
        f"{p['episodes']}. Made by `{command}`.",
    ]
    return "\n".join(lines) + "\n"


def curve_figure(
    curve: list[tuple[int, float]], zero: float, label: str, keep_best: bool = True
) -> Figure:
    """The learning curve with the zero action's return as a line.

    Parameters
    ----------
    curve : list of (int, float)
        (training steps, mean return on the curve's seeds).
    zero : float
        The zero action's mean return on the same seeds.
    label : str
        The trained controller's legend entry.
    keep_best : bool, optional
        Mark the best point (the policy kept, ARS) rather than the last one (PPO).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 4.0), layout="constrained")
    ax = fig.add_subplot()
    steps, returns = (np.array(v) for v in zip(*curve, strict=True))
    # the axis spans twice the zero action's return unless a third of the points lie below
    # that; the points below the axis sit on its edge
    low = float(np.min(returns))
    if zero < 0 and np.mean(returns < 2.0 * zero) < 1 / 3:
        low = min(2.0 * zero, float(np.max(returns)))
    high = max(float(np.max(returns)), zero) + 0.1 * abs(zero)
    ax.plot(steps, np.maximum(returns, low), "o-", ms=3, label=label)
    below = returns < low
    if below.any():
        note = f"{below.sum()} points below the axis (lowest {returns.min():.0f})"
        ax.plot(steps[below], np.full(below.sum(), low), "v", color="C3", ms=7, label=note)
    kept = int(np.argmax(returns)) if keep_best else len(returns) - 1
    note = "best: the policy kept" if keep_best else "last: the policy kept"
    ax.plot(steps[kept], max(returns[kept], low), "*", color="C2", ms=12, label=note)
    ax.axhline(zero, color="k", ls="--", label="paper's LQI alone (zero action)")
    ax.set_ylim(low - 0.03 * (high - low), high)
    ax.set_xlabel("training steps (10 ms samples, summed over all copies)")
    ax.set_ylabel("mean episode return, curve seeds")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower left", fontsize=8)
    return fig


def check_docs(algo: str) -> None:
    """Before training: the docs page (with ``algo``'s markers) and the figure's place in
    ``docs/img`` may be written (``cli._script.docs_file``).

    Parameters
    ----------
    algo : str
        "ars" or "ppo".

    Raises
    ------
    TetherheliError
        One line: a link or a file on the way, a missing page or markers.
    """
    docs_file(ROOT, f"{DOC_IMG}/residual_{algo}_curve.png")
    page = docs_file(ROOT, DOC_PAGE)
    _replace_table(page.read_text(encoding="utf-8") if page.is_file() else "", algo, "")


def _replace_table(page: str, algo: str, table_text: str) -> str:
    """``page`` with ``table_text`` between ``algo``'s markers."""
    begin, end = table_markers(algo)
    head, sep, rest = page.partition(begin)
    _, sep_end, tail = rest.partition(end)
    if not sep or not sep_end:
        raise TetherheliError(
            f"--update-docs: {DOC_PAGE} lacks the markers {begin!r} and {end!r}; allowed: "
            "the repository's page (git checkout it)"
        )
    return f"{head}{begin}\n{table_text}{end}{tail}"


def update_docs(algo: str, figure: Path, table_text: str) -> None:
    """Copy the figure to ``docs/img`` and put the table between the page's markers (the
    project's own files, replaced whole: ``cli._script.write_docs_file``).

    Parameters
    ----------
    algo : str
        "ars" or "ppo" (names the figure and the markers).
    figure : Path
        The learning curve PNG.
    table_text : str
        :func:`table`'s text.

    Returns
    -------
    None
    """
    check_docs(algo)
    page = (ROOT / DOC_PAGE).read_text(encoding="utf-8")
    write_docs_file(ROOT, f"{DOC_IMG}/{figure.name}", figure.read_bytes())
    write_docs_file(ROOT, DOC_PAGE, _replace_table(page, algo, table_text))


def table_markers(algo: str) -> tuple[str, str]:
    """The docs page's markers around the table of ``algo``.

    Parameters
    ----------
    algo : str
        "ars" or "ppo".

    Returns
    -------
    tuple of str
        The opening and closing HTML comments.
    """
    return (
        f"<!-- residual-{algo}-table: written by examples/train_residual.py -->",
        f"<!-- /residual-{algo}-table -->",
    )


def run(args: argparse.Namespace, command: str) -> dict:
    """Train, evaluate and write the outputs into ``args.out`` (whole, at the end:
    ``_io.output_directory``).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (see ``parser``), checked by ``check_arguments``.
    command : str
        The command line, quoted in the table.

    Returns
    -------
    dict
        What ``residual_<algo>.json`` holds.
    """
    from tetherheli._io import output_directory
    from tetherheli.viz.figure import save_figure

    algo = args.algo
    steps = DEFAULT_STEPS[algo] if args.steps is None else args.steps
    curve_seeds = [CURVE_SEED + i for i in range(args.curve_episodes)]
    zero_curve = float(np.mean(evaluate(zero_policy, curve_seeds)["return"]))
    print(f"zero action on the curve's {len(curve_seeds)} seeds: mean return {zero_curve:.3f}")
    extra: dict[str, Any] = {}
    files: dict[str, Callable[[Path], object]] = {}  # file name -> writes it at that path
    if algo == "ars":
        gains, curve, seconds = train_ars(
            steps, args.seed, args.eval_every or 1, args.curve_episodes,
            ars={"directions": args.directions, "episodes": args.episodes},
        )  # fmt: skip
        policy = linear_policy(gains)
        label = "LQI + linear residual (ARS)"
        files["residual_ars_gains.npy"] = lambda path: np.save(path, gains)
        extra["gains"] = gains.tolist()
    else:
        import torch

        torch.set_num_threads(args.threads)
        model, normalize, curve, seconds = train_ppo(
            steps, args.seed, args.n_envs, args.eval_every or 50_000, args.curve_episodes
        )
        policy = sb3_policy(model, normalize)
        label = "LQI + PPO residual (deterministic)"
        files["residual_ppo_model.zip"] = model.save
        files["residual_ppo_vecnormalize.pkl"] = lambda path: normalize.save(str(path))
    trained = curve[-1][0]
    print(f"trained {trained:,d} steps in {seconds:.0f} s")
    test_seeds = [TEST_SEED + i for i in range(args.test_episodes)]
    runs = {
        "zero action": evaluate(zero_policy, test_seeds),
        "lqi feedback x2": evaluate(linear_policy(lqi_feedback_gains(1.0)), test_seeds),
        "policy": evaluate(policy, test_seeds),
    }
    figures = summary(runs)
    labels = {
        "zero action": "paper's LQI (zero action)",
        "lqi feedback x2": "paper's LQI, state feedback doubled (hand-made residual)",
        "policy": label,
    }
    text = table(figures, command, labels)
    record = {
        "algo": algo,
        "task": TASK,
        "settings": {k: v for k, v in vars(args).items() if k not in ("debug", "force")},
        "trained_steps": trained,
        "seconds": seconds,
        "curve": curve,
        "curve_zero_action": zero_curve,
        "test_seeds": [test_seeds[0], test_seeds[-1]],
        "figures": figures,
        **extra,
    }
    fig = curve_figure(curve, zero_curve, label, keep_best=algo == "ars")
    figure = f"residual_{algo}_curve.png"
    files[figure] = lambda path: save_figure(fig, path, dpi=120)
    files[f"residual_{algo}_table.md"] = lambda path: path.write_text(text, encoding="utf-8")
    files[f"residual_{algo}.json"] = lambda path: path.write_text(
        json.dumps(record, indent=1), encoding="utf-8"
    )
    assert sorted(files) == sorted(output_names(algo)), sorted(files)
    writer = f"train_residual.py --algo {algo}"  # ars and ppo keep each other's files
    with output_directory(args.out, writer=writer, force=args.force) as tmp:
        for name, write in files.items():
            write(tmp / name)
    print(text)
    out = Path(args.out)
    for name in (figure, f"residual_{algo}_table.md", f"residual_{algo}.json"):
        print(f"wrote {out / name}")
    if args.update_docs:
        update_docs(algo, out / figure, text)
        print(f"updated {DOC_IMG}/{figure} and {DOC_PAGE}")
    return record


#: Default training steps per algorithm (each about 3-5 minutes on two shared cores).
DEFAULT_STEPS = {"ars": 15_000_000, "ppo": 1_000_000}
#: The largest values of the counts (each also bounded by the memory its environment copies
#: need: ``check_arguments``).
MAX_STEPS = 10**9
MAX_EPISODES = 10_000
MAX_COPIES = 1024


def parser() -> argparse.ArgumentParser:
    """The command line (every value checked as it is parsed: one line, exit 2).

    Returns
    -------
    argparse.ArgumentParser
        Its flags.
    """
    p = script_parser(__file__, __doc__)
    p.add_argument(
        "--algo", choices=("ars", "ppo"), default="ars",
        help="ars: linear residual by random search (default); ppo: Stable-Baselines3 PPO",
    )  # fmt: skip
    p.add_argument(
        "--steps", type=count_arg("--steps", 1, MAX_STEPS), default=None,
        help="training steps (default 15000000 for ars, 1000000 for ppo)",
    )  # fmt: skip
    p.add_argument(
        "--seed", type=count_arg("--seed", 0, 2**31 - 1), default=0,
        help="seed of the training (default 0)",
    )  # fmt: skip
    p.add_argument(
        "--directions", type=count_arg("--directions", 1, MAX_COPIES),
        default=ARS_SETTINGS["directions"],
        help=f"ars: directions per iteration (default {ARS_SETTINGS['directions']})",
    )  # fmt: skip
    p.add_argument(
        "--episodes", type=count_arg("--episodes", 1, MAX_COPIES),
        default=ARS_SETTINGS["episodes"],
        help=f"ars: episodes per candidate (default {ARS_SETTINGS['episodes']})",
    )  # fmt: skip
    p.add_argument(
        "--n-envs", type=count_arg("--n-envs", 1, MAX_COPIES), default=32,
        help="ppo: environment copies (default 32)",
    )  # fmt: skip
    p.add_argument(
        "--eval-every", type=count_arg("--eval-every", 1, MAX_STEPS), default=None,
        help="between curve points: iterations (ars, default 1) or steps (ppo, default 50000)",
    )  # fmt: skip
    p.add_argument(
        "--curve-episodes", type=count_arg("--curve-episodes", 1, MAX_EPISODES), default=20,
        help="episodes per curve point (default 20)",
    )  # fmt: skip
    p.add_argument(
        "--test-episodes", type=count_arg("--test-episodes", 2, MAX_EPISODES), default=100,
        help="held-out test episodes (default 100)",
    )  # fmt: skip
    p.add_argument(
        "--threads", type=count_arg("--threads", 1, 1024), default=1,
        help="PyTorch threads (default 1)",
    )  # fmt: skip
    out_argument(p, "residual_out")
    p.add_argument(
        "--update-docs", action="store_true",
        help="copy the figure and the table into docs/ (docs/studies/residual_policy.md)",
    )  # fmt: skip
    return p


def output_names(algo: str) -> list[str]:
    """The files a run of ``algo`` writes into ``--out``.

    Parameters
    ----------
    algo : str
        "ars" or "ppo".

    Returns
    -------
    list of str
        The figure, the table, the record, then the gains or the model and its
        normalisation.
    """
    own = (
        ["residual_ars_gains.npy"]
        if algo == "ars"
        else ["residual_ppo_model.zip", "residual_ppo_vecnormalize.pkl"]
    )
    return [
        f"residual_{algo}_curve.png",
        f"residual_{algo}_table.md",
        f"residual_{algo}.json",
        *own,
    ]


def check_arguments(args: argparse.Namespace) -> None:
    """What the values allow, checked before anything runs or is written: ``--algo ppo``'s
    packages, the output folder (``cli._script.claim``), the docs files of
    ``--update-docs``, and the memory of the most environment copies flown at once
    (``env_checks.check_env_memory``, the environments' own rule).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Raises
    ------
    TetherheliError
        One line naming the argument.
    """
    from tetherheli.envs.checks import check_env_memory
    from tetherheli.envs.env import TetheredHoverEnv
    from tetherheli.resources import ResourceLimitError

    if args.algo == "ppo" and importlib.util.find_spec("stable_baselines3") is None:
        raise TetherheliError(
            "--algo ppo needs Stable-Baselines3 and PyTorch; allowed: --algo ars, or pip "
            'install "tetherheli[rl]"'
        )
    claim(args.out, force=args.force, names=output_names(args.algo))
    if args.update_docs:
        check_docs(args.algo)
    sizes = {"--curve-episodes": args.curve_episodes, "--test-episodes": args.test_episodes}
    if args.algo == "ars":
        sizes["2 x --directions x --episodes"] = 2 * args.directions * args.episodes
    else:
        sizes["--n-envs"] = args.n_envs
    flags = max(sizes, key=sizes.__getitem__)
    env = TetheredHoverEnv(**TASK)
    try:
        check_env_memory(env.scenario, sizes[flags], env.gust_dt)
    except ResourceLimitError as exc:
        raise ResourceLimitError(f"{flags} = {sizes[flags]}: {exc}") from None


def main(argv: Sequence[str] | None = None) -> int:
    """Run the example.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 on success, 2 on a bad argument or output folder (one line on stderr, nothing
        run or written).
    """

    def work(arguments: list[str]) -> int:
        args = parser().parse_args(arguments)
        check_arguments(args)
        run(args, " ".join(["python examples/train_residual.py", *arguments]))
        return 0

    return run_script(__file__, work, None if argv is None else list(argv))


if __name__ == "__main__":
    raise SystemExit(main())

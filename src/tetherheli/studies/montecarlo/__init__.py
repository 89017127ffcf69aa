"""Monte Carlo of a wind scenario, free against tethered, memory-bounded and resumable.

The dispersions are a ``[montecarlo]`` table in a scenario TOML file (the rest of the file is
an ordinary scenario, see ``tetherheli.scenario.core``; its ``configuration`` is ignored,
because every draw is run both "free" and "tethered")::

    [montecarlo]
    runs = 1000                        # number of draws N (the CLI's --runs overrides)
    seed = 20261122                    # root seed (the CLI's --seed overrides)
    amplitude_std_percent = 20.0       # wind magnitude scale ~ max(0, N(1, s / 100))
    direction_std_deg = 10.0           # wind direction rotated about n3 by N(0, s) deg
    random_phase = false               # sine phases ~ U(0, 2 pi) instead of the file's
    start_jitter_s = 0.5               # whole wind profile shifted in time by N(0, s) s
    params = { "helicopter.m_F" = 5.0, "tether.K_C" = 10.0 }
                                       # parameter uncertainty: factor ~ U(1 - p/100, 1 + p/100)

Definitions:

- one time shift, one rotation and one scale per draw apply to every wind component (pulse,
  step, sine, constant); the time shift moves the whole profile (starts clipped at 0 s, sine
  phases shifted by -2 pi f shift, so the sine keeps its shape relative to its start);
- a turbulence component gets a fresh gust series per draw (seed = the root seed, spawn key
  (i, 0): a stream independent of the draw's dispersions) and its mean wind is rotated by the
  draw's direction; amplitude scale and time shift do not apply to it (gust statistics);
- parameter uncertainty p% is a uniform band of half-width p% about the nominal value
  (0 <= p < 100), percentages of amplitude std are limited to [0, 100];
- **the controller is designed on the nominal parameters** (the LQI gain of the file's
  parameters, ``run_batch(design_params=...)``); the plant is the dispersed one, and the
  trim operating point (initial state, references, trim inputs) is the dispersed plant's own
  hover trim;
- seeds: draw i uses child i of ``numpy.random.SeedSequence(seed).spawn(N)`` only, so a draw
  does not depend on N, the chunking or the number of workers. That child is
  ``SeedSequence(seed, spawn_key=(i,))``, made per chunk (``draw_seed``): memory before and
  during the run is O(chunk), not O(N). The table records the child's entropy and spawn key.

Failed runs are data: a run that fails in flight (diverges, hits the ground, ...) or whose
dispersed plant cannot be set up (no hover trim within the actuator limits:
``Status.SETUP``, the error in the ``reason`` column) is a row with its status, and the
job goes on. In the statistics a failed run counts as the worst value (+inf; -inf for
``tension_min``), so it sits in the tail of the failing side instead of being dropped
(``statistics``: the percentiles, the paired per-draw reduction by the tether and the
bootstrap confidence intervals).

Output directory (``run_montecarlo_chunks`` runs the draws and returns the finished
``MonteCarloJob``; ``report.montecarlo.run_montecarlo`` writes its results folder):
``results.csv`` (one row per run and configuration; ``reason`` says why a draw could not be
set up; ``release_time``, ``release_tension`` record a tether release by the safety device,
NaN without one), ``summary.json`` (configuration, version, N, seed, percentiles with
bootstrap confidence intervals, the paired reduction, failed draws, releases per
configuration) and the figures of one metric (``metric``, default peak_q1):
``<metric>_hist.png``, ``<metric>_cdf.png``, ``<metric>_paired.png`` (or .pdf, .svg).
Work is done in chunks written (fsync, then rename) to ``partial/chunk_<first>_<end>.csv``:
the chunk's rows of ``results.csv`` and a last line ``# tetherheli montecarlo chunk: draws
a..b, n rows, sha256 <hex of the rows>``. Running the same command again verifies every
finished chunk against that line (and each row's column count and draw), computes a damaged
one again after naming it on stderr, and skips the others; running it with a larger N extends
the job (the first draws are reused: draw i does not depend on N).
"""

from .config import (
    CONFIGURATIONS,
    MAX_RUNS,
    MonteCarloConfig,
    load_montecarlo,
    montecarlo_config_from_dict,
)
from .draws import Draw, draw, draw_seed
from .runner import MonteCarloJob, run_montecarlo_chunks

__all__ = [
    "CONFIGURATIONS",
    "MAX_RUNS",
    "Draw",
    "MonteCarloConfig",
    "MonteCarloJob",
    "draw",
    "draw_seed",
    "load_montecarlo",
    "montecarlo_config_from_dict",
    "run_montecarlo_chunks",
]

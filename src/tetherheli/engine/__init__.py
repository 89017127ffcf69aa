"""The compiled engine: the sample step and its phases, the closed loop, the lanes (blocks of
runs advanced together), the step driven from Python, the on-line summary.

Internal: the engine takes packed arrays that ``tetherheli.runs`` builds from a scenario; the
public entry points are :func:`tetherheli.simulate` and :func:`tetherheli.run_batch`.
"""

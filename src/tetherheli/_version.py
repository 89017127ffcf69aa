"""The installed package version (recorded next to every result)."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("tetherheli")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"


#: Distributions whose versions decide a run's numbers (python-control is ``control``).
RECORDED_DISTRIBUTIONS = ("numpy", "scipy", "numba", "control")


def dependency_versions() -> dict[str, str | None]:
    """The installed versions of ``RECORDED_DISTRIBUTIONS`` (None: not installed)."""
    found: dict[str, str | None] = {}
    for name in RECORDED_DISTRIBUTIONS:
        try:
            found[name] = version(name)
        except PackageNotFoundError:
            found[name] = None
    return found


def git_commit() -> str | None:
    """The commit of the git work tree holding this package's source, or None (an installed
    wheel, no git, or not a repository); a tree with uncommitted changes gets ``+dirty``."""
    import subprocess
    from pathlib import Path

    here = Path(__file__).resolve().parent

    def git(*args: str) -> str | None:
        try:
            done = subprocess.run(
                ["git", "-C", str(here), *args],
                capture_output=True,
                text=True,
                timeout=10,
                check=False,
            )
        except (OSError, subprocess.SubprocessError):
            return None
        return done.stdout.strip() if done.returncode == 0 else None

    if git("ls-files", "--error-unmatch", "_version.py") is None:
        return None  # not the repository's source (e.g. installed inside another repository)
    commit = git("rev-parse", "HEAD")
    if not commit:
        return None
    dirty = git("status", "--porcelain", "--untracked-files=no", "--", ".")
    return f"{commit}+dirty" if dirty else commit

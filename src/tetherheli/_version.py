"""The installed package version (recorded next to every result)."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("tetherheli")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"

"""The cable alone (issue 23): a lumped-mass cable (``Cable``) flown between a fixed anchor
and a prescribed top motion with the very chain step the engine uses (``drive_cable``)."""

from ._cable import Cable, CableRun, drive_cable

__all__ = ["Cable", "CableRun", "drive_cable"]

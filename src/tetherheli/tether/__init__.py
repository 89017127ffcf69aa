"""The tether: the lumped-mass chain (``lumped``: its forces, stiff-stable step and the
coupling to the helicopter), its static shape (``catenary``: Irvine's elastic catenary, the
static cable in wind, the tether as a sensor with sag), the hover trim with a massive tether
(``lumped_trim``) and the drum winch (``winch``).

Exported here, the cable alone: a lumped-mass cable (``Cable``) flown between a
fixed anchor and a prescribed top motion with the very chain step the engine uses
(``drive_cable``), and the same cable in MoorDyn v2 (``drive_moordyn``; the optional
``validation`` extra)."""

from ._cable import Cable, CableRun, drive_cable
from ._moordyn import buoyant_gravity, drive_moordyn, moordyn_input

__all__ = ["Cable", "CableRun", "buoyant_gravity", "drive_cable", "drive_moordyn", "moordyn_input"]

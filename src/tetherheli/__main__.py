"""``python -m tetherheli`` is the ``tetherheli`` command."""

from .cli import main

raise SystemExit(main())

"""``python -m guidewire``: see :mod:`guidewire.app.cli`."""

import sys

from .app.cli import main

sys.exit(main())

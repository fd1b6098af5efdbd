"""``python -m guidewire``: see :mod:`guidewire.cli`."""

import sys

from .cli import main

sys.exit(main())

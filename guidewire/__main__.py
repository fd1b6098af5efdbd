"""``python -m guidewire``: see :mod:`guidewire.app.cli`."""

from .app.cli import entry

entry()

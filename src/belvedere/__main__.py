"""``python -m belvedere``."""

from belvedere.cli import console

console()

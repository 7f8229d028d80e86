"""``python -m sandlight``: the command-line interface (works without the console script on PATH)."""

from sandlight.cli import main

main()

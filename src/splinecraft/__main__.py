"""``python -m splinecraft``: the ``splinecraft`` console script (:func:`splinecraft.cli.main`)."""
import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())

"""python -m imfoc ...: the same as the console script `imfoc` (imfoc.cli)."""
import sys

from .cli import main

sys.exit(main())

"""``python -m mtcal.cli ARGS`` = ``mtcal ARGS``."""
import sys

from mtcal.cli import main

sys.exit(main())

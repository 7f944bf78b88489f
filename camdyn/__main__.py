"""``python -m camdyn ...``: the same as the ``camdyn`` console script."""

import sys

from .cli import main

sys.exit(main())

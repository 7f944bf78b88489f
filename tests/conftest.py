import os

os.environ.setdefault("EQX_ON_ERROR", "nan")  # as the CLI runs: solver results are checked explicitly

import camdyn.model  # noqa: E402,F401  (float64 on)

# SPDX-License-Identifier: MIT
"""python -m pneufrac_reduce: the pneufrac-reduce command."""
import sys

from .cli import main

sys.exit(main())

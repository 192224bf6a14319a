# SPDX-License-Identifier: MIT
"""An independent simulator of the paper's pneumatic controllers, for testing
pneufrac-fit's diagnosis (see docs/analysis-indep.md)."""

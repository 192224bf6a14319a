# SPDX-License-Identifier: MIT
"""pneufrac-plot: draws the CSV files that `pneufrac bode` and `pneufrac step`
write, for their --plot option (the C tools write no images themselves).

    pneufrac-plot bode CSV PNG
    pneufrac-plot step CSV PNG

Exit status: 0 success; 2 bad arguments or an unreadable CSV; 3 numpy or
matplotlib is missing. Errors are one line on stderr.
"""

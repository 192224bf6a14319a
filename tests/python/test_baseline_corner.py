# SPDX-License-Identifier: MIT
"""A baseline group left at a bound of its range is not reported identified
(issue 8; baseline.corners).

The independent simulator's lag-real seed 1 (dd, two steps, AR(1) noise, a
24 ms lag; docs/analysis-bench.md, "Where the large lags are lost") ends its
baseline with rho at 1e4, beta at 1 and q at 0. Before baseline.corners
the report called the three "identified", with 95 % intervals across the
bound (rho [8614, 11610], beta [0.963, 1.035], q [-0.0069, 0.0069]).

The rule is checked from the groups' ranges (cases.bound_faults), not from
baseline.corners; every diagnosis of cases.check and test_diagnose_indep
is checked by it too."""
import pytest

import cases
from pneufrac_fit import model, output


@pytest.fixture(scope="module")
def diag(lag_real_1):
    """The record's diagnosis, shared with another file (conftest.SHARED)."""
    return lag_real_1


def _at_bound(d) -> list[str]:
    return [g for g in d.baseline.free_groups if g in model.GROUPS and g != "K"
            and cases.near_bound(d.pb.setup, g, d.baseline.groups[g])]


def test_groups_at_a_bound_are_not_identified(diag, tmp_path):
    d = diag
    at = _at_bound(d)
    assert at, "premise: this record's baseline leaves a free group at a bound"
    assert cases.bound_faults(d) == []
    report = output.write_report(d, tmp_path).read_text(encoding="utf-8")
    rows = {ln.split("|")[1].strip(): ln for ln in report.splitlines()
            if ln.startswith("| ") and ln.count("|") == 6}
    for g in at:
        status = rows[g].split("|")[5]
        assert "identified" in status and "not identified" in status, rows[g]
        assert "bound" in status, rows[g]


def test_corners_change_no_fit(diag):
    """Only what is reported changes: the groups at a bound keep their
    fitted values, and every group called identified was free."""
    d = diag
    assert set(d.corners) == set(_at_bound(d))
    for g, c in d.corners.items():
        assert c["value"] == pytest.approx(d.baseline.groups[g], rel=1e-12)
    assert all(g in d.baseline.free_groups for g, v in d.identified.items() if v)

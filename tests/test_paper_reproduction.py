"""``reproduce-paper --quick``: the verdicts, issue 8's acceptance on the wagon, results.json holding every
plotted point, and the README section generated from it (so the README cannot drift from the code)."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from cof_gym.commands.paper import PAPER_COFS, exit_status, reproduce, summary_lines
from cof_gym.commands.paper_readme import readme_section, render_section
from cof_gym.analysis.theory import paper_schedule
from cof_gym.physics.contact_geometry import creep_stiffness_constant, hertz_semi_axes, kalker_c11
from cof_gym.physics.creep import OperatingConditions, creep_curve

README = Path(__file__).resolve().parents[1] / "README.md"
NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?")


@pytest.fixture(scope="module")
def run(tmp_path_factory) -> tuple[dict, Path]:
    out = tmp_path_factory.mktemp("paper")
    return reproduce(out, quick=True), out


@pytest.fixture(scope="module")
def results(run) -> dict:
    return run[0]


def test_every_check_holds_and_no_fail_is_printed(results: dict) -> None:
    assert [c["name"] for c in results["checks"] if not c["passed"]] == []
    assert exit_status(results) == 0
    assert not any("FAIL" in line for line in summary_lines(results))


def test_a_failing_check_exits_non_zero(results: dict) -> None:
    broken = {**results, "checks": [*results["checks"], {"name": "x", "passed": False, "detail": "d"}]}
    assert exit_status(broken) == 1
    assert any(line.strip().startswith("FAIL  x") for line in summary_lines(broken))


@pytest.mark.parametrize("cof", PAPER_COFS)
def test_kalker_slope_reproduces_the_paper_on_the_wagon(results: dict, cof: float) -> None:
    """Issue 8 acceptance: counter torque, laden, 10 m/s, 5 Hz, 345 N m, kA = kS = 1."""
    z = results["wagon"]["dry_kalker"]["cofs"][str(cof)]["zero_crossing"]
    assert 0.92 <= z["fraction_interpolated"] <= 0.96
    assert -0.08 <= z["cof_error_relative"] <= -0.03


def test_dry_shape_keeps_its_crossing_and_the_model_explains_it(results: dict) -> None:
    """Polach's dry set crosses at ~70-79 % (its knee), rising with the CoF, as the small-signal model says."""
    entries = results["wagon"]["dry"]["cofs"]
    crossings = [entries[str(c)]["zero_crossing"]["fraction_interpolated"] for c in PAPER_COFS]
    assert all(0.69 <= x <= 0.80 for x in crossings)
    assert crossings == sorted(crossings)
    for c in PAPER_COFS:
        e = entries[str(c)]
        assert e["zero_crossing"]["fraction_interpolated"] == pytest.approx(e["model_crossing_fraction"], abs=0.01)
    mech = results["mechanism"]
    assert mech["k_cross"] == pytest.approx(mech["k_cross_estimate"], rel=0.01)


def test_results_json_holds_every_plotted_point(run: tuple[dict, Path]) -> None:
    results, out = run
    stored = json.loads((out / "results.json").read_text())
    n = len(paper_schedule())
    for cof in PAPER_COFS:
        rows = stored["half_wheelset"]["cofs"][str(cof)]
        assert len(rows) == n
        for r in rows:
            assert math.isfinite(r["phase_sim_deg"]) and math.isfinite(r["phase_eq3_deg"])
            assert (r["ladder"] is None) == r["within_tolerance"]
        for shape in ("dry", "dry_kalker"):
            assert len(stored["wagon"][shape]["cofs"][str(cof)]["steps"]) == n
    assert {p["shape"] for p in stored["mechanism"]["stiffness"]} == {"dry", "dry_kalker"}
    for name in stored["figures"]:
        assert (out / name).stat().st_size > 10_000


def test_readme_section_matches_a_fresh_quick_run(results: dict) -> None:
    """The README's "What reproduce-paper shows" is what `cof-gym reproduce-paper --quick --readme README.md` writes: same
    text, and every number within one unit of its last printed digit of a fresh --quick run."""
    fresh, current = render_section(results), readme_section(README)
    assert NUMBER.sub("#", current) == NUMBER.sub("#", fresh), "README text differs: run cof-gym reproduce-paper --quick --readme README.md"
    for old, new in zip(NUMBER.findall(current), NUMBER.findall(fresh)):
        unit = 10.0 ** -(len(old.split(".")[1]) if "." in old else 0)
        assert abs(float(old) - float(new)) <= 1.01 * unit, f"README {old} vs fresh run {new}"


def test_readme_creep_law_constants_match_the_code() -> None:
    """The **Creep laws** paragraph's c11, C and initial slopes are the code's values."""
    text = README.read_text()
    para = text[text.index("**Creep laws**"):text.index("**Models**")]
    a, b = hertz_semi_axes(100e3)
    c11 = float(re.search(r"c11 = ([\d.]+)", para).group(1))
    assert c11 == pytest.approx(kalker_c11(a / b), abs=0.005)
    assert float(re.search(r"C = ([\d.]+) at 100 kN", para).group(1)) == pytest.approx(creep_stiffness_constant(100e3), abs=0.05)
    slopes = re.search(r"dCoA/ds = ([\d.]+) \(dry\) and ([\d.]+) \(dry_kalker\)", para)
    for value, condition in zip(slopes.groups(), ("dry", "dry_kalker")):
        initial = creep_curve(1e-9, OperatingConditions(cof=0.4, condition=condition))[1][0]
        assert float(value) == pytest.approx(initial, abs=0.05)


def test_the_compliant_wheelset_model_refuses_constants_that_divide_by_zero_or_turn_it_around() -> None:
    from cof_gym.analysis.theory import CompliantWheelset, crossing_fraction
    from cof_gym.physics.vehicle import wagon_parameters

    base = CompliantWheelset.of_wagon(wagon_parameters(), 10.0)
    assert base.phase_lag_deg(20.0, 2 * math.pi * 5) < 0.0  # the speed lags the torque
    for field, value in (("speed_m_s", 0.0), ("speed_m_s", -10.0), ("contact_load_n", 0.0), ("mass_kg", math.nan),
                         ("kx_n_m", math.inf), ("cx_n_s_m", -1.0)):
        with pytest.raises(ValueError, match=f"CompliantWheelset.{field} must be a"):
            CompliantWheelset(**{**base.__dict__, field: value})
    assert CompliantWheelset(**{**base.__dict__, "cx_n_s_m": 0.0}).cx_n_s_m == 0.0  # no damper is a model too
    with pytest.raises(ValueError, match="omega_m must be a finite number > 0"):
        crossing_fraction(base, OperatingConditions(cof=0.3), 0.0)

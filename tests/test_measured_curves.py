"""A measured creep curve as the env's table (cof_gym/physics/measured_curves.py) and ``cof-gym evaluate
--creep-table`` (cof_gym/commands/suites.py): the isotonic fit is the least-squares non-decreasing sequence, the
table rises strictly to exactly 1 at the measured CoF, and every malformed file or point is one line naming it."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cof_gym import cli
from cof_gym.commands.suites import read_measured_curve
from cof_gym.physics.measured_curves import isotonic_fit, measured_table
from cof_gym.physics.native import layout

VALUES = st.lists(st.floats(-10, 10, allow_nan=False), min_size=1, max_size=40)


def test_isotonic_fit_pools_each_falling_run_into_its_mean() -> None:
    np.testing.assert_allclose(isotonic_fit([1, 3, 2, 4, 3.5, 5]), [1, 2.5, 2.5, 3.75, 3.75, 5])
    np.testing.assert_array_equal(isotonic_fit([3, 2, 1]), [2, 2, 2])


@settings(max_examples=200, deadline=None)
@given(VALUES)
def test_isotonic_fit_is_non_decreasing_keeps_the_sum_and_is_nearest(values: list[float]) -> None:
    fit = isotonic_fit(values)
    x = np.asarray(values)
    tol = 1e-9 * (1 + np.abs(x).sum())  # the pooled means' rounding
    assert np.all(np.diff(fit) >= -tol)
    assert abs(fit.sum() - x.sum()) <= tol * len(x)
    for other in (np.sort(x), np.full(len(x), x.mean()), np.maximum.accumulate(x)):  # other non-decreasing sequences
        assert ((fit - x) ** 2).sum() <= ((other - x) ** 2).sum() + tol


def _curve(s: np.ndarray) -> np.ndarray:
    """A CoA curve peaking at 0.18 at creepage 0.008 and falling by a quarter by 0.04."""
    return 0.18 * np.where(s < 0.008, 1 - (1 - s / 0.008) ** 3, 1 - 0.25 * (s - 0.008) / 0.032)


def test_a_clean_measurement_is_the_table_itself_at_its_peak_cof() -> None:
    s = np.array([0.001, 0.002, 0.004, 0.008, 0.016, 0.03])
    table, cof = measured_table(s, _curve(s))
    assert cof == pytest.approx(0.18, rel=1e-12)
    np.testing.assert_allclose(table.creepage, np.r_[0.0, s], rtol=1e-12)
    np.testing.assert_allclose(np.array(table.adhesion_ratio) * cof, np.r_[0.0, _curve(s)], rtol=1e-12)
    assert table.peak_index == 4 and table.adhesion_ratio[4] == 1.0


def test_scattered_repeated_points_become_a_strictly_rising_table_within_the_native_size() -> None:
    rng = np.random.default_rng(1)
    s = np.repeat(np.geomspace(2e-4, 0.04, 100), 2)  # every creepage measured twice
    table, cof = measured_table(s, _curve(s) + rng.normal(0, 0.002, len(s)))
    ratio = np.array(table.adhesion_ratio)
    assert len(ratio) <= layout.MAX_TABLE_POINTS and ratio[table.peak_index] == 1.0
    assert np.all(np.diff(ratio[:table.peak_index + 1]) > 0) and np.all(np.diff(table.creepage) > 0)
    assert abs(cof / 0.18 - 1) < 0.05  # the fit's maximum: above the curve's by about the scatter


@pytest.mark.parametrize("rise,fall", [(100, 2), (2, 100), (1, 100), (100, 0), (64, 64)])
def test_a_long_measurement_keeps_its_peak_within_the_native_table(rise: int, fall: int) -> None:
    """However the points split between the branches, the table holds at most the native size, the peak among them."""
    s = np.r_[np.linspace(0.01 / rise, 0.01, rise), np.linspace(0.012, 0.03, fall)]  # the peak at 0.01 in each
    coa = np.r_[np.linspace(0.3 / rise, 0.3, rise), np.linspace(0.29, 0.2, fall)]
    table, cof = measured_table(s, coa)
    assert 3 <= len(table.creepage) <= layout.MAX_TABLE_POINTS and cof == pytest.approx(0.3, rel=1e-12)
    assert table.creepage[table.peak_index] == pytest.approx(0.01, rel=1e-12)
    assert len(table.creepage) == min(1 + rise + fall, layout.MAX_TABLE_POINTS)


@pytest.mark.parametrize("creepage,coa,fragment", [
    ([0.001], [0.1], "two or more points"),
    ([0.0, 0.001, 0.002], [0.05, 0.1, 0.12], "CoA at creepage 0 must be 0"),
    ([0.001, -0.002], [0.1, 0.12], "creepage must be finite and >= 0, got -0.002 at point 1"),
    ([0.001, 0.002], [0.1, float("nan")], "CoA must be finite and >= 0, got nan at point 1"),
    ([0.001, 3.0], [0.1, 0.12], "creepage must be at most 2"),
    ([0.001, 0.002], [0.0, 0.0], "CoA above 0"),
])
def test_a_bad_measurement_is_refused_naming_the_point(creepage, coa, fragment: str) -> None:
    with pytest.raises(ValueError, match=fragment.replace("(", r"\(")):
        measured_table(creepage, coa)


def test_points_that_read_no_creep_force_above_creepage_0_are_left_to_the_tables_origin() -> None:
    """A force sensor at zero (or scatter clipped at it) at the smallest creepages: the table starts from (0, 0), the
    points above it unchanged; one point left above 0 after the fit is refused as a measured curve's error."""
    table, cof = measured_table([0.0005, 0.001, 0.002, 0.004], [0.0, 0.0, 0.1, 0.2])
    np.testing.assert_array_equal(table.creepage, [0.0, 0.002, 0.004])
    np.testing.assert_array_equal(table.adhesion_ratio, [0.0, 0.5, 1.0])
    assert cof == 0.2
    for coa in ([0.0, 0.2], [0.0, 0.0, 0.2]):
        with pytest.raises(ValueError, match="a measured creep curve needs two or more points after its fit"):
            measured_table([0.001, 0.002, 0.003][:len(coa)], coa)


POINTS = st.lists(st.tuples(st.floats(0, 2, allow_nan=False), st.floats(0, 1, allow_nan=False)), min_size=1,
                  max_size=80)


@settings(max_examples=300, deadline=None)
@given(POINTS)
def test_any_finite_measurement_is_a_valid_table_or_refused_as_a_measured_curve(points) -> None:
    """Whatever points a user measured within the accepted ranges, the answer is a table the env accepts (the
    measured maximum as its CoF) or one ValueError about the measured curve, never the table's own checks."""
    s, coa = [p[0] for p in points], [p[1] for p in points]
    try:
        table, cof = measured_table(s, coa)
    except ValueError as e:
        assert str(e).startswith("a measured"), e
        return
    by_creepage: dict[float, list[float]] = {}
    for x, a in points:
        by_creepage.setdefault(x, []).append(a)
    assert cof == pytest.approx(max(np.mean(a) for x, a in by_creepage.items() if x > 0), rel=1e-12)
    assert 3 <= len(table.creepage) <= layout.MAX_TABLE_POINTS


def _write_csv(path: Path, s: np.ndarray, coa: np.ndarray) -> Path:
    rows = "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(s, coa))
    path.write_text("# a twin-disc run\ncreepage,coa\n\n" + rows)
    return path


def test_evaluate_plays_a_measured_curve_at_its_cof_in_every_episode(tmp_path: Path) -> None:
    s = np.geomspace(5e-4, 0.03, 12)
    path = _write_csv(tmp_path / "twin_disc.csv", s, _curve(s))
    options = read_measured_curve(path)
    assert options["cof"] == pytest.approx(float(_curve(s).max()), rel=1e-12)
    out = tmp_path / "out"
    assert cli.main(["evaluate", "--agents", "staircase-zeroed", "--creep-table", str(path), "--episodes", "2",
                     "--out", str(out), "--quiet"]) == 0
    with open(out / "episodes.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 2 and {r["creep_family"] for r in rows} == {"table"}
    assert all(float(r["cof"]) == pytest.approx(options["cof"], rel=1e-9) for r in rows)
    assert "creep_table=\"twin_disc\"" in (out / "summary.md").read_text().splitlines()[0]


def _rows(out: Path) -> list[dict[str, str]]:
    with open(out / "episodes.csv") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("header,creepage_scale,coa_scale", [
    ("creepage,coa", 1.0, 1.0), ("creepage [%],traction coefficient", 100.0, 1.0),
    ("Creep (percent),adhesion %", 100.0, 100.0), ("# no header", 1.0, 1.0)])
def test_a_header_in_percent_reads_the_same_curve(header: str, creepage_scale: float, coa_scale: float,
                                                  tmp_path: Path) -> None:
    s = np.geomspace(5e-4, 0.03, 12)
    plain = read_measured_curve(_write_csv(tmp_path / "plain.csv", s, _curve(s)))
    rows = "".join(f"{float(a) * creepage_scale!r},{float(b) * coa_scale!r}\n" for a, b in zip(s, _curve(s)))
    (path := tmp_path / "scaled.csv").write_text(f"{header}\n{rows}")
    scaled = read_measured_curve(path)
    assert scaled["cof"] == pytest.approx(plain["cof"], rel=1e-12)
    np.testing.assert_allclose(scaled["creep_law"]["table"]["creepage"], plain["creep_law"]["table"]["creepage"],
                               rtol=1e-12)


@pytest.mark.parametrize("separated", ["semicolons", "semicolons, decimal points", "tabs", "spaces",
                                       "commas, a semicolon in the header"])
def test_a_spreadsheets_export_reads_the_same_curve(separated: str, tmp_path: Path) -> None:
    """A measured curve exported where the comma is the decimal mark (cells split at semicolons or tabs), or written
    with spaces between its columns, reads as the comma-separated file of the same numbers."""
    s = np.geomspace(5e-4, 0.03, 12)
    plain = read_measured_curve(_write_csv(tmp_path / "plain.csv", s, _curve(s)))
    pairs = [(repr(float(a)), repr(float(b))) for a, b in zip(s, _curve(s))]
    header, rows = {
        "semicolons": ("creepage;CoA", [f"{a.replace('.', ',')};{b.replace('.', ',')}" for a, b in pairs]),
        "semicolons, decimal points": ("creepage;CoA", [f"{a};{b}" for a, b in pairs]),
        "tabs": ("creepage\tCoA", [f"{a.replace('.', ',')}\t{b}" for a, b in pairs]),
        "spaces": ("# creepage, CoA\ncreepage   CoA", [f"{a}   {b}" for a, b in pairs]),
        "commas, a semicolon in the header": ('"creepage; [-]",CoA', [f"{a},{b}" for a, b in pairs]),
    }[separated]
    (path := tmp_path / "export.csv").write_text("\n".join([header, *rows]) + "\n")
    assert read_measured_curve(path) == plain
    # as a spreadsheet writes it: a UTF-8 byte-order mark and Windows line ends, or a Latin-1 header
    path.write_bytes(b"\xef\xbb\xbf" + "\r\n".join(rows).encode())
    assert read_measured_curve(path) == plain
    path.write_bytes("\n".join([header.replace("CoA", "µ [°]"), *rows]).encode("latin-1"))
    assert read_measured_curve(path) == plain
    path.write_bytes("\r\n".join([header, *rows]).encode("utf-16"))  # "Unicode text", its byte-order mark first
    assert read_measured_curve(path) == plain


def test_a_slip_velocity_column_is_refused(tmp_path: Path) -> None:
    (path := tmp_path / "slip.csv").write_text("slip velocity [m/s],coa\n0.01,0.1\n0.05,0.2\n")
    with pytest.raises(ValueError, match="the first column is a slip velocity"):
        read_measured_curve(path)


def test_several_measured_curves_play_the_same_seeds_each_as_one_curve_alone(tmp_path: Path) -> None:
    """Two files: every episode once per curve, the same seeds (the speed, load and sensor draws pair up), each noted
    by its file's name, and each curve's episodes exactly what ``--creep-table`` with that file alone plays."""
    s = np.geomspace(5e-4, 0.03, 12)
    dry = _write_csv(tmp_path / "dry.csv", s, _curve(s))
    wet = _write_csv(tmp_path / "wet.csv", s * 2, 0.5 * _curve(s))
    run = ["evaluate", "--agents", "staircase-zeroed", "--episodes", "2", "--quiet", "--creep-table"]
    assert cli.main([*run, str(dry), str(wet), "--out", str(tmp_path / "both")]) == 0
    both = _rows(tmp_path / "both")
    assert [(r["note"], r["seed"]) for r in both] == [("dry", "0"), ("dry", "1"), ("wet", "0"), ("wet", "1")]
    for key in ("speed_m_s", "load_case", "creepage_offset"):
        assert [r[key] for r in both[:2]] == [r[key] for r in both[2:]]
    for k, path in enumerate((dry, wet)):
        assert cli.main([*run, str(path), "--out", str(tmp_path / path.stem)]) == 0
        alone = _rows(tmp_path / path.stem)
        for key in ("cof", "estimate", "relative_error", "steps"):
            assert [r[key] for r in both[2 * k:2 * k + 2]] == [r[key] for r in alone], key
    assert "note dry" in (tmp_path / "both" / "summary.md").read_text()


def test_a_suite_file_names_measured_curves_beside_it(tmp_path: Path) -> None:
    """``"creep_table": "FILE.csv"`` in a suite file's options (top level or an episode's), relative to the file: the
    curve's table at its own CoF, or at the episode's ``cof``; played by evaluate as given."""
    import json

    from cof_gym.commands.suites import file_suite

    s = np.geomspace(5e-4, 0.03, 12)
    (tmp_path / "curves").mkdir()
    measured = read_measured_curve(_write_csv(tmp_path / "curves" / "dry.csv", s, _curve(s)))
    suite_path = tmp_path / "suite.json"
    suite_path.write_text(json.dumps({"options": {"creep_table": "curves/dry.csv", "speed_m_s": 12.0},
                                      "episodes": [{"seed": 3}, {"seed": 4, "options": {"cof": 0.25}}]}))
    suite = file_suite(suite_path, 1, 0)
    assert suite.episodes[0] == (3, {**measured, "speed_m_s": 12.0})
    assert suite.episodes[1] == (4, {**measured, "speed_m_s": 12.0, "cof": 0.25})
    out = tmp_path / "out"
    assert cli.main(["evaluate", "--agents", "staircase-zeroed", "--suite", str(suite_path), "--out", str(out),
                     "--quiet"]) == 0
    rows = _rows(out)
    assert [float(r["cof"]) for r in rows] == pytest.approx([measured["cof"], 0.25], rel=1e-9)
    assert {r["creep_family"] for r in rows} == {"table"}


@pytest.mark.parametrize("options,fragment", [
    ({"creep_table": "missing.csv"}, "creep_table: "),
    ({"creep_table": "curves/dry.csv", "creep_law": "wet"}, "give creep_table or creep_law, not both"),
    ({"creep_table": 3}, "creep_table must be a CSV file's path"),
])
def test_a_bad_measured_curve_in_a_suite_is_one_line_exit_2(options: dict, fragment: str, tmp_path: Path,
                                                           capsys) -> None:
    import json

    s = np.geomspace(5e-4, 0.03, 12)
    (tmp_path / "curves").mkdir()
    _write_csv(tmp_path / "curves" / "dry.csv", s, _curve(s))
    (suite := tmp_path / "suite.json").write_text(json.dumps({"options": options}))
    assert cli.main(["evaluate", "--suite", str(suite), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--suite" in err and fragment in err, err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("text,extra,fragment", [
    ("creepage,coa\n0.001,0.1\n0.002,abc\n", [], "row 3 is not a creepage and a CoA"),
    ("creepage;coa\n0,001;0,1\n0,002;0,2,5\n", [], "row 3 is not a creepage and a CoA"),  # two decimal commas
    ("\x00\x01", [], "cannot be read as CSV (not a text file"),
    # "creepage [%] CoA" split at its spaces put the percent on the CoA's column
    ("creepage [%]  CoA\n0.1 0.1\n0.3 0.2\n1 0.25\n", [], "a header of columns separated by spaces, names units"),
    ("0.001\n", [], "row 1 is not a creepage and a CoA"),  # a number in it: data, not a header
    ("coa\n", [], "two or more points"),  # a first row without a number is a header
    # a typo in the first row was taken for a header and that point lost; a percent sign after a number for a
    # header saying percent, every later creepage divided by 100
    ("0.0005,O.05\n0.001,0.1\n0.002,0.2\n0.004,0.3\n0.01,0.25\n", [], "row 1 is not a creepage and a CoA"),
    ("0.1%,0.1\n0.2,0.2\n0.4,0.3\n1,0.25\n", [], "row 1 is not a creepage and a CoA"),
    ("creepage,coa\n0.001,0.1\n0.002,0.2\n", ["--env-kwargs", "cof:0.2"], "which --env-kwargs fixes too"),
    ("creepage,coa\n0.001,0.1\n0.0005,-0.2\n", [], "CoA must be finite and >= 0"),
    ("creepage,coa\n0.001,0.1\n0.002,0.2\n", ["--suite", "paper"], "which episode 0 of suite paper fixes too"),
    ("creepage,coa\n0.001,0.35\n0.004,0.7\n", [], "the measured curve's CoF (its largest CoA after the fit) must be"),
    ("creepage,coa\n0.001,0.1\n0.002,0.2\n", ["SAME"], "two files have one name"),
    ("creepage,coa\n0.001,0.1\n0.002,0.2\n", ["SAME", "--episodes", "60000"], "2 curves x 60000 episodes"),
])
def test_a_bad_creep_table_is_one_line_exit_2(text: str, extra: list[str], fragment: str, tmp_path: Path,
                                              capsys) -> None:
    path = tmp_path / "curve.csv"
    path.write_text(text)
    if extra[:1] == ["SAME"]:  # a second file: of the same name, or (with more episodes) another
        (tmp_path / "sub").mkdir()
        other = tmp_path / ("sub/curve.csv" if len(extra) == 1 else "other.csv")
        other.write_text(text)
        extra = [str(other), *extra[1:]]
    assert cli.main(["evaluate", "--creep-table", str(path), *extra, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--creep-table" in err and fragment in err, err
    assert not (tmp_path / "out").exists()


def test_watch_plays_a_measured_curve(tmp_path: Path, capsys) -> None:
    s = np.geomspace(5e-4, 0.03, 12)
    path = _write_csv(tmp_path / "twin_disc.csv", s, _curve(s))
    out = tmp_path / "episode.gif"
    assert cli.main(["watch", "--agent", "staircase-zeroed", "--creep-table", str(path), "--seed", "2", "--out",
                     str(out), "--fps", "4", "--width", "320"]) == 0
    assert out.stat().st_size > 0
    cof = read_measured_curve(path)["cof"]
    assert f"true CoF {cof:.4f}" in capsys.readouterr().out


@pytest.mark.parametrize("creepage, coa", [([True, 0.02], [0.1, 0.2]), ("abc", "def"),
                                           ([[0.01], [0.02]], [[0.1], [0.2]]), (None, None),
                                           ([0.01, 0.02], ["0.1", "0.2"])])
def test_measured_points_that_are_not_flat_numbers_are_refused_naming_them(creepage, coa):
    """True read as creepage 1, text as a conversion error naming nothing, 2-D input as 'got 2 creepages and 2 CoAs'."""
    from cof_gym.physics.measured_curves import measured_table

    with pytest.raises(ValueError, match=r"a measured (creepage|CoA) must be a flat sequence of numbers"):
        measured_table(creepage, coa)

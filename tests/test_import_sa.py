"""SpatialAnalyzer ASCII exports -> tidy recording: round trips through SA text written here in the layouts of
the SA manual ("Exporting ASCII Formatted Points": Collection Group Target x y z, optional uncertainties and time
stamp, space or comma separated, // comments), mapping file and naming pattern, units, bad lines."""
from __future__ import annotations

import json

import numpy as np
import pytest

from mtcal.campaign.simulate import simulate
from mtcal.cli import main
from mtcal.errors import InputError
from mtcal.measurement.import_sa import import_sa
from mtcal.measurement.recordings import format_recording, make_recording, parse_recording, read_recording

PATTERN = r"(?P<axis>[A-Z])_r(?P<round>\d+)_(?P<position>-?[\d.]+)_(?P<point>\w+?)_(?P<direction>up|dn)"


@pytest.fixture(scope="module")
def tidy():
    """A small simulated campaign (X and C, 2 rounds, out and back, time stamps), as read from its CSV; the
    temperature column is not part of an SA export, so it is left out."""
    rec, _ = simulate(rounds=2, seed=3, plan={"axes": {"X": {"start": 0, "stop": 200, "count": 5},
                                                       "C": {"start": -40, "stop": 80, "count": 4}}})
    rec = make_recording(rec.axis, rec.round, rec.position, rec.point, rec.xyz, rec.time_s, rec.direction)
    return parse_recording(format_recording(rec), "tidy.csv")


def _name(rec, i):
    return f"{rec.axis[i]}_r{rec.round[i]}_{rec.position[i]:g}_{rec.point[i]}_{'up' if rec.direction[i] > 0 else 'dn'}"


def _sa_space(rec, scale=1.0):
    lines = ["// SA Version 2021.01.08", "// Working Frame: Machine", "// Units: mm"]
    for i in range(len(rec)):
        x, y, z = rec.xyz[i] / scale
        lines.append(f"Tracker Run{rec.round[i]} {_name(rec, i)} {x:.10f} {y:.10f} {z:.10f} 0.0021 0.0150 0.0148 "
                     f"{rec.time_s[i]:.3f}")
    return "\n".join(lines) + "\n"


def test_round_trip_space_separated_with_pattern(tidy):
    res = import_sa(_sa_space(tidy), "export.txt", pattern=PATTERN)
    assert format_recording(res.recording) == format_recording(tidy)
    assert res.matched == len(tidy) and not res.skipped
    assert any("uncertainties were read" in n for n in res.notes)


def test_round_trip_comma_header_and_inches(tidy):
    head = "// exported with header\nCollection,Group,Target,X,Y,Z,Time\n"
    body = "".join(f"A,B,{_name(tidy, i)},{tidy.xyz[i, 0] / 25.4:.12f},{tidy.xyz[i, 1] / 25.4:.12f},"
                   f"{tidy.xyz[i, 2] / 25.4:.12f},{tidy.time_s[i]:.3f}\n" for i in range(len(tidy)))
    res = import_sa(head + body, "export.csv", pattern=PATTERN, units="in")
    assert format_recording(res.recording) == format_recording(tidy)


def test_round_trip_tab_full_names_with_mapping_file(tidy, tmp_path):
    """Collection::Group::Target in one field, tab separated, date-time stamps; mapping by file."""
    t0 = np.datetime64("2026-03-04T08:00:00")
    lines, rows = [], ["target,axis,round,position,point,direction"]
    for i in range(len(tidy)):
        name = f"T{i:04d}"
        stamp = str(t0 + np.timedelta64(int(round(tidy.time_s[i] * 1000)), "ms")).replace("T", " ")
        lines.append("\t".join([f"Run::Grp::{name}", *(f"{v:.9f}" for v in tidy.xyz[i]), stamp]))
        rows.append(f"{name},{tidy.axis[i]},{tidy.round[i]},{tidy.position[i]:g},{tidy.point[i]},"
                    f"{'+1' if tidy.direction[i] > 0 else '-1'}")
    export, mapping, out = tmp_path / "export.txt", tmp_path / "map.csv", tmp_path / "rec.csv"
    export.write_text("\n".join(lines) + "\n")
    mapping.write_text("\n".join(rows) + "\n")
    assert main(["import-sa", str(export), "--mapping", str(mapping), "-o", str(out)]) == 0
    back = read_recording(out)
    shift = tidy.time_s.min()  # date-time stamps become seconds since the earliest one
    expect = make_recording(tidy.axis, tidy.round, tidy.position, tidy.point, tidy.xyz, tidy.time_s - shift,
                            tidy.direction)
    assert format_recording(back) == format_recording(expect)


def test_imported_campaign_goes_through_iso230_2(tidy, tmp_path, capsys):
    export, out = tmp_path / "export.txt", tmp_path / "rec.csv"
    export.write_text(_sa_space(tidy))
    assert main(["import-sa", str(export), "--pattern", PATTERN, "-o", str(out), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["rows"] == len(tidy)
    assert main(["iso230-2", str(out), "--axis", "X", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["axes"]["X"]["targets"]["n_up"] == [2.0] * 5


def test_unmatched_targets_listed_or_skipped_with_a_count(tidy, tmp_path, capsys):
    text = _sa_space(tidy) + "Tracker Run1 Nest_check 1.0 2.0 3.0 0.01 0.01 0.01 99.0\n"
    with pytest.raises(InputError, match=r"1 target\(s\) match no pattern: Tracker::Run1::Nest_check \(line \d+\)"):
        import_sa(text, "export.txt", pattern=PATTERN)
    res = import_sa(text, "export.txt", pattern=PATTERN, skip_unmatched=True)
    assert len(res.recording) == len(tidy) and res.skipped == [("Tracker::Run1::Nest_check", len(text.splitlines()))]
    export, out = tmp_path / "e.txt", tmp_path / "r.csv"
    export.write_text(text)
    assert main(["import-sa", str(export), "--pattern", PATTERN, "-o", str(out)]) == 2
    assert not out.exists()
    assert main(["import-sa", str(export), "--pattern", PATTERN, "-o", str(out), "--skip-unmatched"]) == 0
    assert "1 left out" in capsys.readouterr().out


@pytest.mark.parametrize("line, message", [
    ("C G X_r1_0_P_up 1.0 abc 3.0", r"export\.txt:3: x y z must be numbers"),
    ("C G X_r1_0_P_up 1.0 2.0", r"export\.txt:3: 5 fields; expected 3 name field\(s\) then x y z"),
    ("C G X_r1_0_P_up 1 2 3 0.1 0.1 0.1 yesterday", r"export\.txt:3: unrecognised field\(s\) after x y z"),
    ("C G Q_r1_0_P_up 1 2 3", r"export\.txt:3: axis 'Q' is not one of"),
    ("C G X_r1_0_P_up 1 2 3", r"export\.txt:3: target C::G::X_r1_0_P_up maps to the same reading as line 2"),
])
def test_bad_lines_named_with_file_and_line(line, message):
    text = "// header comment\nC G X_r1_0_P_up 1 2 3\n" + line + "\n"
    with pytest.raises(InputError, match=message):
        import_sa(text, "export.txt", pattern=PATTERN)


def test_bad_mapping_and_pattern(tmp_path):
    text = "C G T1 1 2 3\n"
    with pytest.raises(InputError, match="named groups"):
        import_sa(text, "e.txt", pattern=r"(?P<axis>\w)")
    with pytest.raises(InputError, match="not a valid regular expression"):
        import_sa(text, "e.txt", pattern=r"(?P<axis>")
    m = tmp_path / "map.csv"
    m.write_text("target,axis,round,position,point\nT1,X,1.5,0,P\n")
    from mtcal.measurement.import_sa import read_mapping
    with pytest.raises(InputError, match=r"e\.txt:1 \(mapping: .*map\.csv:2\): round must be an integer"):
        import_sa(text, "e.txt", mapping=read_mapping(m))
    m.write_text("target,axis,round,position\nT1,X,1,0\n")
    with pytest.raises(InputError, match=r"map\.csv:1: header must be"):
        read_mapping(m)


def test_numeric_target_names_need_the_name_field_count(tmp_path):
    """SA targets are often numbered: 'Coll Grp 12 x y z' has no non-numeric target field to find."""
    m = tmp_path / "map.csv"
    m.write_text("target,axis,round,position,point,direction\n12,X,1,0,P,+\n13,X,1,50,P,+\n")
    from mtcal.measurement.import_sa import read_mapping
    text = "Coll Grp 12 70.0 0.0 10.0\nColl Grp 13 120.0 0.0 10.0\n"
    with pytest.raises(InputError, match=r"e.txt:1: 1 number\(s\) after x y z.*numbered targets need "
                                         r"`name_fields` 3"):
        import_sa(text, "e.txt", mapping=read_mapping(m))
    res = import_sa(text, "e.txt", mapping=read_mapping(m), name_fields=3)
    np.testing.assert_array_equal(res.recording.xyz, [[70, 0, 10], [120, 0, 10]])
    assert res.recording.position.tolist() == [0, 50] and res.recording.direction.tolist() == [1, 1]


def test_header_columns_not_used_are_named():
    text = "Collection,Group,Target,X,Y,Z,RMS\nA,B,X_r1_0_P_up,1,2,3,0.004\n"
    res = import_sa(text, "h.csv", pattern=PATTERN)
    assert res.recording.xyz.tolist() == [[1, 2, 3]] and res.notes == ["h.csv:1: column(s) ['RMS'] not used"]


# ----------------------------------------------------------------------------- issue 20: careless exports
@pytest.mark.parametrize("text,message", [
    ("A B X_r1_0_P_up 70.0 0.0 10.0 0.0025\n", r"e\.txt:1: 1 number\(s\) after x y z.*tolerance"),
    ("Collection,Group,Target,X,Y,Z,X\nA,B,X_r1_0_P_up,1,2,3,4\n", r"e\.txt:1: columns 4 \('X'\) and 7 \('X'\) both"),
    ("A B X_r1_0_P_up 1e308 0.0 10.0\n", r"e\.txt:1: target A::B::X_r1_0_P_up at inf mm after converting from m"),
    ("A B X_r1_0_P_up 70000 0.0 10.0\n", r"e\.txt:1: .* 7e\+07 mm after converting from m.*really in m"),
])
def test_careless_exports_are_refused_naming_line_and_problem(text, message):
    """A tolerance column read as a time, a duplicate X column taken silently, an inf or a wrong --units written
    through (issue 20)."""
    with pytest.raises(InputError, match=message):
        import_sa(text, "e.txt", pattern=PATTERN, units="m")


def test_a_pattern_group_that_takes_no_part_is_named_not_a_key_error():
    with pytest.raises(InputError, match=r"e\.txt:1: target A::B::X_r1_0_P_up matches `pattern` but its group\(s\) "
                                         r"\['axis'\] took no part"):
        import_sa("A B X_r1_0_P_up 70.0 0.0 10.0\n", "e.txt",
                  pattern=r"(?P<axis>Q)?X_r(?P<round>\d+)_(?P<position>[\d.]+)_(?P<point>[A-Z]+)_up")


# ----------------------------------------------------------------------------- issue 36: the file's own units
def _sa_inches(rec, units_line="// Units: Inches"):
    """An SA export as SA writes one in inches: its comment block states the unit (SA User Manual, "Exporting ASCII
    Formatted Points": version, frame and units as leading // lines); coordinates in inches."""
    return _sa_space(rec, scale=25.4).replace("// Units: mm", units_line)


def test_the_exports_units_line_is_read(tidy):
    """`// Units: Inches` converts from inches without being told (main read it as mm: 25.4 times too small)."""
    res = import_sa(_sa_inches(tidy), "export.txt", pattern=PATTERN)
    assert res.units == "in"
    np.testing.assert_allclose(res.recording.xyz, tidy.xyz, rtol=0, atol=1e-8)  # mm, as the tidy campaign's
    for line in ("// Units: Millimeters", "// units = mm"):
        assert import_sa(_sa_space(tidy).replace("// Units: mm", line), "e.txt", pattern=PATTERN).units == "mm"
    assert import_sa(_sa_space(tidy, 1000.0).replace("// Units: mm", "//Units: Meters"), "e.txt",
                     pattern=PATTERN).units == "m"


def test_a_units_option_against_the_files_line_is_refused(tidy):
    with pytest.raises(InputError, match=r"export\.txt:3: the export says its units are in, `units` says mm"):
        import_sa(_sa_inches(tidy), "export.txt", pattern=PATTERN, units="mm")
    assert import_sa(_sa_inches(tidy), "export.txt", pattern=PATTERN, units="in").units == "in"
    with pytest.raises(InputError, match=r"export\.txt:3: the export's units are 'Feet'; mtcal reads"):
        import_sa(_sa_inches(tidy, "// Units: Feet"), "export.txt", pattern=PATTERN)


def test_cli_reads_an_inch_export_without_units(tidy, tmp_path, capsys):
    src = tmp_path / "export.txt"
    src.write_text(_sa_inches(tidy))
    out = tmp_path / "rec.csv"
    assert main(["import-sa", str(src), "--pattern", PATTERN, "-o", str(out)]) == 0
    assert "lengths in -> mm" in capsys.readouterr().out
    np.testing.assert_allclose(read_recording(out).xyz, tidy.xyz, atol=1e-6)
    bad = tmp_path / "rec2.csv"
    assert main(["import-sa", str(src), "--pattern", PATTERN, "--units", "mm", "-o", str(bad)]) == 2
    assert not bad.exists()

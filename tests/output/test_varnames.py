"""Column names mapped to what NetCDF and MATLAB store (issue 24, point 4): one identifier per
name, distinct, the name kept where it already is one."""

import re

import pytest

from rollerrig.output.varnames import MAX_NAME_LENGTH, storable_name, storable_names

IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


@pytest.mark.parametrize(
    ("given", "stored"),
    [
        ("oil temp/bearing", "oil_temp_bearing"),
        ("Group/Channel", "Group_Channel"),
        ("N/mm", "N_mm"),
        ("[bold]x[/bold]", "bold_x_bold"),
        ("Öl-Temp", "Ol_Temp"),
        ("µ-Wert", "Wert"),  # the micro sign has no ASCII letter: dropped
        ("1st harmonic", "v_1st_harmonic"),
        ("_private", "private"),
        ("", "v"),
        ("///", "v"),
        ("温度", "v"),
        ("torque", "torque"),
    ],
)
def test_a_name_becomes_an_identifier(given, stored):
    assert storable_name(given, "nc") == stored
    assert storable_name(given, "mat") == stored


def test_formats_that_store_any_text_keep_every_name():
    names = ["oil temp/bearing", "", "[x]", "Öl"]
    for fmt in ("csv", "parquet", "tdms", "mf4"):
        assert storable_names(names, fmt) == {n: n for n in names}


def test_names_that_collide_after_mapping_get_distinct_suffixes():
    names = ["a/b", "a b", "a_b", "a-b", "time"]
    stored = storable_names(names, "nc", reserved=["time"])
    assert stored == {
        "a/b": "a_b_2",
        "a b": "a_b_3",
        "a_b": "a_b",
        "a-b": "a_b_4",
        "time": "time_2",
    }
    assert len(set(stored.values())) == len(names)


def test_matlab_names_are_cut_to_63_characters_and_stay_distinct():
    names = ["x" * 70 + "/1", "x" * 70 + "/2", "y" * 63]
    stored = storable_names(names, "mat")
    assert all(IDENTIFIER.match(s) and len(s) <= MAX_NAME_LENGTH["mat"] for s in stored.values())
    assert len(set(stored.values())) == 3
    assert stored["y" * 63] == "y" * 63


def test_the_mapping_does_not_depend_on_later_names():
    # An identifier claims its name even when a mapped name before it would become the same.
    assert storable_names(["a b", "a_b"], "mat") == {"a b": "a_b_2", "a_b": "a_b"}


def test_a_single_name_is_refused_not_taken_letter_by_letter():
    """storable_names("torque", "nc") had returned six names, 't', 'o', 'r', ..."""
    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=r"names must be a list of names, got the single "
                       r"name 'torque'; pass \['torque'\]"):  # fmt: skip
        storable_names("torque", "nc")
    with pytest.raises(ParameterError, match="reserved must be a list of names"):
        storable_names(["a"], "mat", reserved="units")
    assert storable_names(["torque"], "nc") == {"torque": "torque"}
    assert storable_names(iter(["a b"]), "nc") == {"a b": "a_b"}  # any iterable of str


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (([5], "nc"), r"names\[0\] must be a str, got 5"),
        ((None, "nc"), "names must be a list of names"),
        ((["a b"], "NC"), "format must be one of .*did you mean 'nc'"),
        ((["a b"], "netcdf"), "format must be one of"),
        ((["a b"], None), "format must be one of"),
    ],
)
def test_names_and_formats_of_the_wrong_kind_are_refused(args, message):
    """An unknown format had kept every name ("NC": names NetCDF cannot store); a name 5
    came back as the key "5"."""
    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=message):
        storable_names(*args)


def test_the_formats_are_those_of_the_writer():
    from rollerrig.output.tables import TABLE_FORMATS
    from rollerrig.output.varnames import FORMATS

    assert tuple(TABLE_FORMATS) == FORMATS
    with pytest.raises(ValueError, match="name must be a str"):
        storable_name(None, "nc")

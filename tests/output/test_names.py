"""Safe output names: Unicode letters and digits kept, everything that can escape the folder or
that a common file system refuses made plain, names of one command's inputs kept distinct."""

import pytest

from rollerrig.output.names import (
    MAX_INPUT_STEM,
    MAX_NAME_BYTES,
    MAX_OUTPUT_STEM,
    safe_file_name,
    safe_file_stem,
    unique_file_stems,
)


def test_unicode_letters_and_digits_are_kept():
    assert safe_file_name("试验一-spectrum.png") == "试验一-spectrum.png"
    assert safe_file_name("试验二-spectrum.png") == "试验二-spectrum.png"
    assert safe_file_name("Mess daten ä ü.json") == "Mess_daten_ä_ü.json"
    assert safe_file_name("a\u0308.csv") == "ä.csv"  # macOS's decomposed form is one letter


@pytest.mark.parametrize(
    ("name", "safe"),
    [
        ("../escaped.nc", "_escaped.nc"),
        ("a/b\\c.png", "a_b_c.png"),
        ('w<i>n:"d|o?w*s.json', "w_i_n__d_o_w_s.json"),
        ("tab\there\x00nul\x7f.csv", "tab_here_nul_.csv"),
        ("...hidden", "hidden"),
        ("trailing. . .", "trailing._._"),
        ("dots...", "dots"),
        ("CON", "CON_"),
        ("nul.json", "nul_.json"),
        ("com1.tar.gz", "com1_.tar.gz"),
        ("Lpt9", "Lpt9_"),
        ("console.json", "console.json"),
        ("", "_"),
    ],
)
def test_what_could_escape_or_be_refused_is_made_plain(name, safe):
    assert safe_file_name(name) == safe


def test_the_length_limit_is_in_bytes_of_utf8():
    name = safe_file_name("试" * 300 + ".png")
    assert name.endswith(".png")
    assert len(name.removesuffix(".png").encode()) <= MAX_OUTPUT_STEM
    assert len(safe_file_name("x." + "y" * 400).encode()) <= MAX_NAME_BYTES
    stem = safe_file_stem("验" * 300)
    assert len(stem.encode()) <= MAX_INPUT_STEM
    assert len(safe_file_name(stem + "-filter-ranking.png").encode()) <= MAX_NAME_BYTES
    assert safe_file_name(stem + "-filter-ranking.png").endswith("-filter-ranking.png")


def test_inputs_of_one_command_get_distinct_stems():
    assert unique_file_stems(["试验一", "试验二"]) == ["试验一", "试验二"]
    assert unique_file_stems(["run", "run"]) == ["run-1", "run-2"]
    assert unique_file_stems(["a b", "a_b"]) == ["a_b-1", "a_b-2"]  # same once made safe
    assert unique_file_stems(["Run", "run"]) == ["Run-1", "run-2"]  # Windows, macOS: one file
    assert unique_file_stems(["x", "x", "x-1"]) == ["x-1-1", "x-2", "x-1"]
    long = unique_file_stems(["y" * 300, "y" * 300])
    assert long[0] != long[1] and all(len(s) <= MAX_INPUT_STEM for s in long)


def test_unique_file_stems_refuses_a_single_name_as_storable_names_does():
    """unique_file_stems("run") had given ['r', 'u', 'n']."""
    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=r"got the single name 'run'; pass \['run'\]"):
        unique_file_stems("run")
    with pytest.raises(ParameterError, match="names must be a list of names"):
        unique_file_stems(5)
    assert unique_file_stems(n for n in ["run", "run"]) == ["run-1", "run-2"]

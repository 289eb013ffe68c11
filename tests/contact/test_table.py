"""Tests for rollerrig.contact.table: creep laws as tables of F/(μN) against ε."""

import re

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.contact.table import creep_table, table_ratio


@pytest.mark.parametrize("nodes", [1, 0, -3, 2.5, True, 10**6])
def test_too_few_too_many_or_non_integer_nodes_are_refused(nodes):
    # One node has no interval to interpolate over: the table failed with an IndexError.
    with pytest.raises(
        ParameterError,
        match=re.escape(f"nodes must be a whole number in [2, 100000] [-], got {nodes!r}"),
    ):
        creep_table("fastsim", nodes=nodes)


def test_two_nodes_make_a_table_that_interpolates():
    t = creep_table("fastsim", nodes=2)
    assert t.values.shape == t.slopes.shape == (2,)
    assert t.step == pytest.approx(t.eps_max)
    assert table_ratio(t, 0.0) == 0.0
    assert table_ratio(t, 2 * t.eps_max) == pytest.approx(t.values[-1])
    assert np.isfinite(table_ratio(t, 0.5 * t.eps_max))

"""The golden record holds: the fixed requests of tests/golden.py print and write what they
did when the record was made (``python tests/golden.py`` remakes it, only for a change that
is meant to change a result, and says so in its commit)."""

from __future__ import annotations

import copy

import pytest
from golden import differences, load_record, run_requests, text_content


@pytest.mark.slow  # eight requests through the command line in a fresh cache (about 2 minutes)
def test_every_number_and_file_is_what_the_golden_record_holds(tmp_path):
    found = list(differences(load_record(), run_requests(tmp_path)))
    assert not found, f"{len(found)} differences from the golden record, the first:\n" + "\n".join(found[:30])


def test_the_comparison_sees_a_number_a_word_and_a_file_change():
    """The comparison itself: a number moved by 1e-8 relative, a word changed, a file added
    or taken away are each reported; a number within 1e-10 relative is not (the tolerance,
    1e-9, between the two)."""
    record = {
        "r": {"stdout": text_content("squeals at 2534.8 Hz, 106.8 dB(A)\n", {}), "files": {"a.csv": {}}}
    }
    assert list(differences(record, copy.deepcopy(record))) == []
    moved = copy.deepcopy(record)
    moved["r"]["stdout"]["numbers"]["values"][0] *= 1 + 1e-8
    assert [d for d in differences(record, moved) if "values[0]" in d]
    within = copy.deepcopy(record)
    within["r"]["stdout"]["numbers"]["values"][0] *= 1 + 1e-10
    assert list(differences(record, within)) == []
    worded = copy.deepcopy(record)
    worded["r"]["stdout"] = text_content("squeals at 2534.8 Hz, 106.8 dB(Z)\n", {})
    assert [d for d in differences(record, worded) if "words" in d]
    added = copy.deepcopy(record)
    added["r"]["files"]["b.png"] = {}
    assert list(differences(record, added)) == ["/r/files/b.png: not in the record"]
    assert list(differences(added, record)) == ["/r/files/b.png: missing"]


def test_a_long_array_is_fingerprinted_so_that_one_value_moved_is_seen():
    """One value of 10 001 moved by 1e-5 relative: the block sums move by 1e-9 of
    themselves, the digest of the values to six digits changes."""
    import numpy as np
    from golden import array_content

    values = np.linspace(1.0, 2.0, 10_001)  # beyond the values kept one by one
    moved = values.copy()
    moved[5_003] *= 1 + 1e-5  # 1e-9 of its block's sum: only the digest of the values sees it
    assert list(differences(array_content(values), array_content(values.copy()))) == []
    assert list(differences(array_content(values), array_content(moved)))

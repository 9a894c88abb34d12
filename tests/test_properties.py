"""Properties of the metric and scoring functions, over random inputs (hypothesis)."""

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from simpick.compare import metrics
from simpick.score import scoring

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)
series = st.lists(finite, min_size=1, max_size=400)
positive = st.floats(min_value=1e-6, max_value=1e6, allow_nan=False, allow_infinity=False)


@given(series, st.randoms(use_true_random=False))
def test_mean_and_range_do_not_depend_on_sample_order(values, rnd):
    shuffled = list(values)
    rnd.shuffle(shuffled)
    a, b = metrics.axis_stats(values), metrics.axis_stats(shuffled)
    assert math.isclose(a["mean"], b["mean"], rel_tol=1e-9, abs_tol=1e-6)
    assert math.isclose(a["range"], b["range"], rel_tol=1e-9, abs_tol=1e-6)


@given(series)
def test_range_is_never_negative_and_never_exceeds_max_minus_min(values):
    r = metrics.trimmed_range(values)
    assert r >= 0
    assert r <= max(values) - min(values) + 1e-6 * (1 + abs(max(values)) + abs(min(values)))


@given(
    st.dictionaries(
        st.sampled_from("xyz"), st.fixed_dictionaries({"mean": finite, "range": positive}), min_size=3, max_size=3
    )
)
def test_error_against_itself_is_zero(stats):
    assert metrics.test_error(stats, stats) == 0.0


@given(st.dictionaries(st.text(min_size=1, max_size=5), positive, min_size=1, max_size=6))
@settings(max_examples=200)
def test_scores_lie_in_zero_one_and_the_best_scores_one(values):
    for fn, best in (
        (scoring.accuracy_scores, min),
        (scoring.efficiency_scores, min),
        (scoring.real_time_factor_scores, max),
    ):
        scores = fn(values)
        assert all(0.0 <= s <= 1.0 + 1e-12 for s in scores.values())
        winner = best(values, key=values.get)
        assert math.isclose(scores[winner], 1.0)


@given(st.lists(finite, min_size=2, max_size=200), st.floats(min_value=-100, max_value=100))
def test_range_ignores_a_constant_offset(values, offset):
    shifted = np.asarray(values) + offset
    assert math.isclose(metrics.trimmed_range(values), metrics.trimmed_range(shifted), rel_tol=1e-6, abs_tol=1e-4)

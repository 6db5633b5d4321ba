"""The likelihood a filter network is fitted under (``FitSettings.loss``): the Gaussian's location is the
conditional mean, the Laplace's the conditional median, the point that minimises the expected absolute
log error (the relative CoF error the task scores, to first order)."""

from __future__ import annotations

import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator.training import (
    FIT_LOSSES, Dataset, FitSettings, collect, fit_member, negative_log_likelihood,
)


def test_each_likelihood_is_least_at_its_location_statistic():
    """Over a grid of locations with a fixed scale, the summed Laplace NLL of seven zeros and three ones is
    least at their median (0) and the Gaussian's at their mean (0.3): exact arithmetic, to the grid step."""
    y = np.array([0.0] * 7 + [1.0] * 3)
    grid = np.linspace(-0.5, 1.5, 2001)  # step 0.001
    totals = {loss: negative_log_likelihood(loss, y[None, :] - grid[:, None], np.zeros((1, len(y)))).sum(axis=1)
              for loss in FIT_LOSSES}
    assert grid[np.argmin(totals["laplace"])] == pytest.approx(0.0, abs=1e-9)
    assert grid[np.argmin(totals["gaussian"])] == pytest.approx(0.3, abs=1e-3)


def test_the_laplace_scale_fitted_is_the_mean_absolute_residual():
    """At a fixed location the Laplace NLL over ``log_var`` is least where ``b = sqrt(var / 2)`` is the mean
    absolute residual (d/db of ``|r| / b + ln b`` summed), the Gaussian's where ``var`` is the mean square."""
    r = np.array([0.1, -0.3, 0.2, 0.6])
    log_vars = np.linspace(-6.0, 2.0, 80001)
    laplace, gaussian = (negative_log_likelihood(loss, r[None, :], log_vars[:, None]).sum(axis=1)
                         for loss in ("laplace", "gaussian"))
    b = np.sqrt(np.exp(log_vars[np.argmin(laplace)]) / 2.0)
    assert b == pytest.approx(np.mean(np.abs(r)), rel=1e-3)
    assert np.exp(log_vars[np.argmin(gaussian)]) == pytest.approx(np.mean(r**2), rel=1e-3)


def test_an_unknown_loss_names_the_field():
    with pytest.raises(ValueError, match="loss must be one of"):
        FitSettings(loss="squared")


def test_a_laplace_member_predicts_the_median_where_a_gaussian_one_predicts_the_mean():
    """Real climbs whose correction target is replaced by a two-valued draw independent of the readings (80 %
    at 0, 20 % at 1: median 0, mean 0.2): the member fitted under the Laplace loss predicts near 0, the
    Gaussian one near 0.2 (the median over the windows of each member's prediction; the half-way point 0.1
    separates them)."""
    data = collect(cof_gym.WAGON_ENV_ID, [{}, {"counter_torque": True}], 12, first_seed=2_000_000)
    rng = np.random.default_rng(0)
    targets = data.targets.copy()
    targets[:, 1] = (rng.random(len(targets)) < 0.2).astype(float)
    skewed = Dataset(data.readings, data.counter_torque, targets, data.episode)
    predicted = {}
    for loss in FIT_LOSSES:
        member = fit_member(skewed, seed=0, settings=FitSettings(hidden=(4,), epochs=150, batch_size=32, loss=loss))
        predicted[loss] = float(np.median(member(skewed.features)[0][:, 1]))
    assert predicted["laplace"] < 0.1 < predicted["gaussian"]

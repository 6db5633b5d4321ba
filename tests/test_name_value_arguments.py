"""The shared ``NAME=VALUE`` argument types (cof_gym/commands/args.py, cof_gym/commands/suites.py): a value is
JSON or, where it is no JSON, the text; a scenario option is refused at parse time unless the env accepts it,
with the field and its allowed range named (the experiments' ``--scenario`` and ``--set`` use them)."""

from __future__ import annotations

import argparse

import pytest

from cof_gym.commands.args import name_value
from cof_gym.commands.suites import scenario_option


def test_values_are_json_or_the_text_itself() -> None:
    assert name_value("noise_level=3") == ("noise_level", 3)
    assert name_value("creep_sticky=false") == ("creep_sticky", False)
    assert name_value("creep_until=null") == ("creep_until", None)
    assert name_value("condition=dry") == ("condition", "dry")
    assert name_value("creep_law={\"family\": \"polach\"}") == ("creep_law", {"family": "polach"})
    assert name_value("a=b=c") == ("a", "b=c")  # the first "=" splits


@pytest.mark.parametrize("text", ["noise_level", "=3", "noise_level="])
def test_a_malformed_item_is_refused(text: str) -> None:
    with pytest.raises(argparse.ArgumentTypeError, match="expected NAME=VALUE"):
        name_value(text)


def test_a_scenario_option_is_one_the_env_accepts() -> None:
    assert scenario_option("noise_level=3") == ("noise_level", 3)
    assert scenario_option("load_case=laden") == ("load_case", "laden")
    assert scenario_option("motor_lag_s=0.1") == ("motor_lag_s", 0.1)


@pytest.mark.parametrize("text, named", [("noise_level=3.5", "noise_level must be a finite number in [0, 3]"),
                                         ("motor_lag_s=1", "motor_lag_s must be a finite number in [0, 0.1] s"),
                                         ("noise_level=loud", "noise_level must be a number"),
                                         ("condition=icy", "condition must be one of"),
                                         ("lag=0", "unknown scenario option"),
                                         ("noise_level=null", "noise_level needs a value")])
def test_a_bad_scenario_option_names_the_field_and_its_range(text: str, named: str) -> None:
    with pytest.raises(argparse.ArgumentTypeError) as error:
        scenario_option(text)
    assert named in str(error.value)

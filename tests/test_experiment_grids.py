"""The scenario grids the README's results use are what experiments/make_grids.py writes: a grid file
edited by hand (or a generator change that moves a published grid) fails here."""

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments"))
from make_grids import (  # noqa: E402
    CONFIRMATION_SETS, SUITES, TORQUE_CONFIRMATION_SETS, all_grids, grid_text, same_grid, v2_heldout_grids)

GRIDS = all_grids()


@pytest.mark.parametrize("name", sorted(GRIDS))
def test_grid_file_is_the_generators_output(name):
    assert same_grid(json.loads((SUITES / f"{name}.json").read_text()), json.loads(grid_text(GRIDS[name])))


def test_same_grid_tells_a_moved_grid_from_rounding():
    """The comparison passes last-place differences (as two CPUs write them) and fails a real change,
    a new key or a changed type."""
    def grid(cof=0.43974034680642626, foot=7.668457089314204e-08, seed=3, note="a", **extra):
        return {"episodes": [{"seed": seed, "note": note, "options": {"cof": cof, "ratio": [foot, 1.0]}}], **extra}

    assert same_grid(grid(), grid(cof=0.4397403468064263, foot=7.668457077630264e-08))
    for moved in (grid(cof=0.4397403478), grid(foot=7.67e-08), grid(seed=4), grid(note="b"),
                  grid(cof="0.43974034680642626"), grid(seed=3.0), grid(extra=1)):
        assert not same_grid(grid(), moved)


def test_heldout_grids_share_no_seed_and_no_shape():
    heldout = {name: spec for name, spec in GRIDS.items() if "heldout" in name and name.startswith("v2")}
    seeds = [e["seed"] for spec in heldout.values() for e in spec["episodes"]]
    assert len(seeds) == len(set(seeds))
    notes = [{e["note"] for e in spec["episodes"]} for spec in heldout.values()]
    assert sum(len(n) for n in notes) == len(set().union(*notes))


def test_every_v2_heldout_file_is_reported_in_the_order_written():
    """The README, its targets and the training report list the v2 held-out grids from
    v2_heldout_grids(): a new grid file is picked up there, each with its own label."""
    listed = v2_heldout_grids()
    assert set(listed) == {p.stem for p in SUITES.glob("v2_heldout*_grid.json")}
    assert list(listed)[:2] == ["v2_heldout_grid", "v2_heldout2_grid"]
    assert list(listed.values())[:2] == ["v2 held-out grid", "v2 second held-out grid"]
    assert len(set(listed.values())) == len(listed)


def test_every_confirmation_grid_file_belongs_to_a_listed_set():
    """The committed confirmation grids are the three of each set in CONFIRMATION_SETS (the eight written so far)."""
    files = {p.stem for p in SUITES.glob("v2_confirmation*_grid.json")}
    listed = {f"v2_{name}{kind}_grid" for name in CONFIRMATION_SETS for kind in ("", "_procedural", "_steep")}
    assert files == listed and len(CONFIRMATION_SETS) >= 8


@pytest.mark.parametrize("prefix", [f"v2_{name}_" for name in CONFIRMATION_SETS])
def test_confirmation_grids_share_no_episode_with_any_other_v2_grid(prefix):
    """A choice confirmed on a confirmation set is confirmed on episodes that took no part in it: no
    seed and no tabulated creep curve of its three grids is on any other v2 grid (validation, reporting
    or the other confirmation set)."""
    v2 = {name: spec for name, spec in GRIDS.items() if name.startswith("v2_")}
    confirmation = {name for name in v2 if name.startswith(prefix)}
    assert len(confirmation) == 3

    def seeds_and_curves(names):
        episodes = [e for name in names for e in v2[name]["episodes"]]
        return ({e["seed"] for e in episodes},
                {repr(e["options"]["creep_law"]) for e in episodes if "creep_law" in e["options"]})

    mine, others = seeds_and_curves(confirmation), seeds_and_curves(set(v2) - confirmation)
    assert mine[0] and mine[1] and not mine[0] & others[0] and not mine[1] & others[1]


def test_the_torque_validation_grids_spread_the_torque_gain_over_what_the_env_accepts():
    """Each grid of the torque sets (validation, every confirmation set) fixes every episode's torque gain error within what the env accepts, spread
    over it (each third of the range holds about a third of the episodes, both signs past the v2 draws), the other
    options as their kind's grid writes them, on seeds no other v2 grid plays."""
    from cof_gym.task.sensors import SYSTEMATIC_ERRORS

    span = SYSTEMATIC_ERRORS["torque_gain_error"]
    torque = {name: spec for name, spec in GRIDS.items() if "torque" in name}
    assert len(torque) == 3 * (1 + len(TORQUE_CONFIRMATION_SETS))
    for spec in torque.values():
        gains = [e["options"]["torque_gain_error"] for e in spec["episodes"]]
        assert all(-span.accepted <= g <= span.accepted for g in gains)
        thirds = [sum(lo <= g < lo + 2 * span.accepted / 3 for g in gains)
                  for lo in (-span.accepted, -span.accepted / 3, span.accepted / 3)]
        assert max(thirds) - min(thirds) <= 2 and sum(thirds) == len(gains)
        assert min(gains) < -span.drawn and max(gains) > span.drawn
    others = {e["seed"] for name, spec in GRIDS.items() if name.startswith("v2_") and name not in torque
              for e in spec["episodes"]}
    seeds = [e["seed"] for spec in torque.values() for e in spec["episodes"]]
    assert not others & set(seeds) and len(seeds) == len(set(seeds))

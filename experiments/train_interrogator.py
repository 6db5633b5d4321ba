"""Train, select and report the learned interrogator (cof_gym/agents/interrogator/). 2 cores, CPU.

    python experiments/train_interrogator.py --out runs/interrogator [--ship]

The recipe since session 30 (rule 42: the guard also learns the climb it slows; rule 45, session 31: the
probing guard steers beside it) runs in three steps:

    python experiments/train_interrogator.py --out runs/interrogator
    python experiments/train_estimator.py --policy runs/interrogator/ensemble --set ceiling_stop=false \
        --out runs/estimator_env --climbs env=8000 --collect-only
    python experiments/train_interrogator.py --out runs/interrogator --reuse \
        --add-guard-climbs runs/estimator_env/onpolicy_env_DIGEST.npz --probing-guard --ship

The first fits the filter and the probing guard and selects the climb; the second has that agent, without
the crest stop (CEILING_STOP, below; the agent shipped until session 30), climb the recipe's 8000 training
episodes on the env's draws (its own climbs, ``DIGEST`` naming its networks and climb; session 26 collected
the same climbs as ``onpolicy_env_56d6d6f9b007.npz``, the digest since changed by a field's default);
the third keeps the filter (fitted on the same climbs: OUT/training.json), fits the guard again on its
climbs and those (OUT/guard/training.json differs), fits the first step's guard again as a second guard
(``--probing-guard``: OUT/probing_guard/, on the probing climbs alone; or keeps it where it is there),
selects the same climb (the selection plays the filter alone; ADOPTED_CLIMB, the parts later rules adopted, is set
after it) and ships. On task v3's wagon (``--env CofGym/TorqueInterrogationInService-v3`` on all three; session 88)
the second step's cache is ``onpolicy_env_DIGEST_v3.npz`` and ``--ship`` writes the ``interrogator-in-service``
package (``cof_gym.agents.policy_files.SHIPPED_INTERROGATORS``).

1. **Data**: training climbs on the v2 wagon's randomisation, half with the paper's counter torque
   (cof_gym/agents/interrogator/training.py): probing climbs steered by their own readings, never by
   the truth, from the collections of COLLECTIONS (``--climbs NAME=N``; the recipe: ``torque_wide=8000``,
   the env's draws with the torque gain anywhere within +-15 %, since session 48, rule 74; ``env=8000``
   before): on the env's creep-law draws (seeds from 1 000 000 on), on procedural creep curves, tables
   beyond every family (from 1 100 000 on), on the env's draws with 8-20 Hz modulations (from 1 200 000 on) and with
   modulation ratios of 10-80 % instead of 3-40 % (from 1 300 000 on), with the deployed probe only
   (from 1 400 000 on), with the climb's jump to the lowest CoF the task admits (from 1 500 000 on;
   lost on validation in session 9), on procedural curves with steep falling branches (from
   1 600 000 on) and with a two-tone excitation (tone 2 at 10-20 Hz, from 1 700 000 on; a filter of its
   own, selected with ``--grid two_tone``; lost on validation in session 11), and more of the env's own
   draws (``env_more``, from 1 800 000 on; lost on validation in session 15); far from every evaluation
   seed; cached in OUT/climbs*.npz.
2. **Seeds**: one filter network per seed (bootstrap resample of the training episodes, its own
   initialisation), OUT/seed_K/; the ensemble of all seeds in OUT/ensemble/. **The guard**
   (``--guard-climbs``; the recipe, session 16: ``env=8000 procedural=8000``; since session 48
   ``torque_wide=8000 procedural_torque_wide=8000``): networks fitted alike (same seeds and fit) on the
   family climbs and the procedural ones together, OUT/guard/seed_K/ and OUT/guard/ensemble/; it steers
   the chosen climb beside the filter and may only slow it (the climb follows the lowest cautious headroom
   of all). Adopted by a rule written before the confirmation grids
   were played (docs/interrogator.md, session 16); since session 30 (rule 42) it also learns the climbs of
   the agent the first two steps ship (``--add-guard-climbs``, above), and since session 31 (rule 45) the
   first step's guard steers beside it (``--probing-guard``). With a guard, a chosen filter estimate becomes
   GUARDED_ESTIMATE: the guards' corrections pooled at every window, without the filter's (rule 46, session
   32; the filter's and the guards' pooled from rule 44, session 31, and from session 20's rule 16 on only
   where the climb stopped on its headroom; it changes no step of the climb). Every chosen climb's estimate
   is at least its best crest bound (CREST_FLOOR: the measured CoA's cycle crest less one phase bin's
   standard error; rule 21, session 22; it changes no step of the climb either), and between stops it
   reports what a runaway in the coming window would measure (RUNAWAY_ESTIMATE: rule 23, session 23; no step
   changes, nor the estimate of an episode that does not run away); once the crest has fallen under a rising
   torque crest, every estimate is at most the best crest plus one bin's standard error (CREST_CEILING: rule
   28, session 25; no step changes either), and the climb ends at that window (CEILING_STOP: rule 30's stop,
   adopted with rule 42, session 30); where the predicted headroom is above CEILING_NEAR_HEADROOM, only a fall
   beyond CEILING_FALL_Z standard errors of the two crests counts (rule 50, session 33: a noisier sensor's
   chance falls far below the peak no longer stop the climb; at the draws' noise no validation climb changed);
   where the climb's first three windows read more speed noise than NOISE_REFERENCE_NMS (``r`` times: the lock-in
   fit's phase error times the response amplitude, ``Reading.lockin_noise_nms``), its cautions are ``r **
   -NOISE_CAUTION_EXPONENT`` and its slow probe's threshold ``r ** NOISE_CREEP_EXPONENT`` times the chosen ones
   (rule 53, session 35: with three times the draws' noise the climb ends fewer climbs far below the peak; at the
   draws' noise no validation climb changed).
3. **Selection, validation only**: the climb's parameters (modulation ratio, target headroom,
   caution, largest step, a slow probe while the headroom is uncertain, whether it stays slow and where
   it ends, the jump to the lowest CoF the task admits: GRIDS;
   a 15 Hz modulation, ratios of 0.05-0.3 and 0.6, cautions of 1.25 and 3, a largest step of 0.4, larger
   steps far from the peak, a target of 0.04 and a slow probe only above a std of 0.12 lost in earlier
   selections), played with the ensemble
   in both vehicle configurations on experiments/suites/v2_validation_grid.json (the v2 draws, 144
   episodes) and experiments/suites/v2_validation_procedural_grid.json (procedural creep curves beyond
   every family, none of the held-out shapes; 108 episodes). Ranking: fewest macro-slips on the family
   grid, then, over both grids pooled with a macro-slip counted as a failed measurement (100 % error),
   the lowest P90, then median relative error. The selection plays the filter alone (with ``--guards``
   networks, if given); the recipe's guard joins the chosen climb. Written to every OUT/*/manifest.json.
4. **Report** (nothing is chosen here): every seed and the ensemble on the default suite (60 episodes),
   on the held-out grids (experiments/suites/v2_heldout*_grid.json) and on the procedural
   validation grid (traction balance;
   per seed, where the selection played the ensemble); per seed median / P90 / macro-slips, and over
   seeds x scenarios the interquartile mean (IQM) of the relative error with a stratified-bootstrap
   95 % CI (runs resampled within each scenario; Agarwal et al. 2021). OUT/report.md, OUT/report.json.
5. ``--ship`` copies OUT/ensemble into cof_gym/agents/policies/interrogator (the ``interrogator`` agent), or with
   ``--env CofGym/TorqueInterrogationInService-v3`` into cof_gym/agents/policies/interrogator_in_service (the
   ``interrogator-in-service`` agent); the package's model card stays.

``--report-only`` plays step 4 alone on the shipped agent as it is (no climb cache: seed K is the package's member K
alone beside the shipped guards, the ensemble the package), e.g. after a rule changed the shipped climb and no network;
with ``--env``, the package shipped for that id (``cof_gym.agents.policy_files.SHIPPED_INTERROGATORS``).
``--fit-only`` stops after step 2: networks for another run's ``--guards`` or crest_tradeoff.py's ``--run``
(``--loss laplace``: fitted under the Laplace likelihood, each output the conditional median; session 26);
``--guard-climbs none`` fits no guard (the recipe before session 16). ``--add-climbs FILE ...`` adds climbs
recorded elsewhere to the filter's (not the guard's): e.g. ``train_estimator.py``'s cache of a deployed
interrogator's own climbs (``OUT/onpolicy_env_DIGEST.npz``), so that the filter also learns the readings of
the climb it steers (session 28, rule 37); ``--add-guard-climbs FILE ...`` adds them to the guard's; the
manifest names the files. ``--torque-balance-lag DEG`` fits every network on the readings a climb with
``torque_balance`` and ``torque_balance_max_lag_deg=DEG`` reads (each climb's torque readings divided by the gain its
first window's torque balance reads: ``Dataset.calibrated``; session 47, rule 72), recorded in OUT/training.json and
the manifest; the recipe's since session 48 (rule 74) is the shipped climb's bound, 65 deg (``none``: the readings as
read, the recipe before).
"""

from __future__ import annotations

import argparse
import hashlib
import itertools
import json
import shutil
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Callable

import gymnasium as gym
import numpy as np

import cof_gym
from cof_gym.agents.interrogator import (
    INTERVAL_FILE, SHIPPED_INTERROGATOR, ClimbParameters, FilterEnsemble, FilterNetwork, interrogator_for, manifest_climb,
    write_manifest,
)
from cof_gym.agents.interrogator.networks import ensemble_files, member_files
from cof_gym.agents.policy_files import MANIFEST_FILE, SHIPPED_INTERROGATORS, TRAINING_RECORD
from cof_gym.agents.interrogator.training import (
    FAR_PEAK_CREEPAGE, FIT_LOSSES, FITTABLE_BLOCKS, STEEP_FALL, TRAINING_SEED, ClimbDraws, Dataset, FitSettings,
    collect_parallel, fit_member, nll,
)
from cof_gym.commands.args import DistinctValues, Parser, float_in_range, positive_int, seed_int
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.commands.suites import make_suite, with_env_id
from cof_gym.task.scenarios import MOTOR_LAG_MAX_S, NOISE_LEVEL_MAX
from cof_gym.task.sensors import SYSTEMATIC_ERRORS

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from make_grids import v2_heldout_grids  # noqa: E402
from ppo_seeds import iqm, stratified_bootstrap_ci  # noqa: E402
from selection import error_summary  # noqa: E402
from script_checks import check_out_dir, load_climbs  # noqa: E402

ENV_ID = cof_gym.WAGON_ENV_ID
# the ids a recipe may be run on (--env), each with the package --ship writes (SHIPPED_INTERROGATORS): the v2 wagon
# (``interrogator``) and task v3's wagon (a speed probe and an irregular track drawn; session 87;
# ``interrogator-in-service``, rule 144, session 88); each collection's climbs are collected on the run's id, the
# selection's validation grids and the report's suites played on it
TRAINING_ENV_IDS = tuple(SHIPPED_INTERROGATORS)
CONFIGS = [{}, {"counter_torque": True}]  # the two vehicle configurations trained on
# draws past the env's own, up to what the env accepts: the sensors' noise (multiples of the full scale) and the
# drive's lag (s) where the env draws 0-1 and 0-0.03 s, and the torque gain error where it draws +-5 %
PAST_DRAWS_NOISE_AND_LAG = {"noise_levels": (0.0, NOISE_LEVEL_MAX), "motor_lags_s": (0.0, MOTOR_LAG_MAX_S)}
_TORQUE_GAIN_ACCEPTED = SYSTEMATIC_ERRORS["torque_gain_error"].accepted
ENCODER_LAGS_S = (0.0, 0.02)  # the encoder lags (s) of the *_encoder collections (rule 110): 0-32 deg at 5 Hz
WIDE_TORQUE_GAIN = {"sensor_errors": (("torque_gain_error", -_TORQUE_GAIN_ACCEPTED, _TORQUE_GAIN_ACCEPTED),)}
# the training climbs: name -> (cache file in OUT, first seed, what the climbs draw beyond the env's own
# randomisation (cof_gym.agents.interrogator.training.ClimbDraws)), and how many of each the recipe uses
COLLECTIONS = {
    "env": ("climbs.npz", TRAINING_SEED, ClimbDraws()),
    # more of the env's own draws (seeds from 1 800 000): sharper on the families, more macro-slips on steep
    # falling branches; lost on validation in session 15 (docs/interrogator.md; experiments/learning_curve.py)
    "env_more": ("climbs_env_more.npz", TRAINING_SEED + 800_000, ClimbDraws()),
    "procedural": ("climbs_procedural.npz", TRAINING_SEED + 100_000, ClimbDraws(shapes="procedural")),
    "high_frequency": ("climbs_high_frequency.npz", TRAINING_SEED + 200_000, ClimbDraws(frequencies_hz=(8.0, 20.0))),
    "wide_probe": ("climbs_wide_probe.npz", TRAINING_SEED + 300_000, ClimbDraws(amplitude_ratios=(0.1, 0.8))),
    # the shipped climb's own probe (40 % at 5 Hz), which the env collection draws in one climb of ten
    "deployed_probe": ("climbs_deployed_probe.npz", TRAINING_SEED + 400_000,
                       ClimbDraws(frequencies_hz=(5.0, 5.0), amplitude_ratios=(0.3, 0.5))),
    # the env's draws, with the deployed climb's jumps to the lowest CoF the task admits (margins 0.1-0.5)
    "floor_jump": ("climbs_floor_jump.npz", TRAINING_SEED + 500_000, ClimbDraws(floor_margins=(0.1, 0.5))),
    # procedural creep curves with steep falling branches (cof_gym.agents.interrogator.training.STEEP_FALL)
    "procedural_steep": ("climbs_procedural_steep.npz", TRAINING_SEED + 600_000,
                         ClimbDraws(shapes="procedural", fall=STEEP_FALL)),
    # the env's draws with a two-tone excitation: tone 2 at 10-20 Hz, weight 0.5-1.5 (a filter of its own)
    "two_tone": ("climbs_two_tone.npz", TRAINING_SEED + 700_000, ClimbDraws(tone2_hz=(10.0, 20.0))),
    # the env's draws with a modulation that shrinks as the slope falls (power 0.5-2, down to 3 %): the
    # readings of a crest-capped climb (ClimbParameters.crest_fraction; session 17)
    "crest_shrink": ("climbs_crest_shrink.npz", TRAINING_SEED + 900_000, ClimbDraws(crest_powers=(0.5, 2.0))),
    "procedural_crest_shrink": ("climbs_procedural_crest_shrink.npz", TRAINING_SEED + 1_000_000,
                                ClimbDraws(shapes="procedural", crest_powers=(0.5, 2.0))),
    # the env's draws and procedural curves with the frequency raised as 1 / speed below a reference speed of
    # 10-40 m/s (a speed-scheduled climb's readings: ClimbParameters.frequency_reference_m_s; session 27)
    "speed_scaled": ("climbs_speed_scaled.npz", TRAINING_SEED + 1_300_000,
                     ClimbDraws(frequency_references_m_s=(10.0, 40.0))),
    "procedural_speed_scaled": ("climbs_procedural_speed_scaled.npz", TRAINING_SEED + 1_400_000,
                                ClimbDraws(shapes="procedural", frequency_references_m_s=(10.0, 40.0))),
    # the env's draws and procedural curves with the sensors' noise at 0-3 times the full scale and the drive's
    # lag at 0-0.1 s (the env's draws: 0-1 and 0-0.03 s), what the env accepts (session 33)
    "noisy": ("climbs_noisy.npz", TRAINING_SEED + 1_500_000, ClimbDraws(**PAST_DRAWS_NOISE_AND_LAG)),
    "procedural_noisy": ("climbs_procedural_noisy.npz", TRAINING_SEED + 1_600_000,
                         ClimbDraws(shapes="procedural", **PAST_DRAWS_NOISE_AND_LAG)),
    # the env's draws and procedural curves with the torque gain error at +-15 %, what the env accepts (the env's
    # draws: +-5 %): the one systematic error that moves the shipped interrogator alone (session 44,
    # experiments/sensor_sensitivity.py)
    "torque_wide": ("climbs_torque_wide.npz", TRAINING_SEED + 1_700_000, ClimbDraws(**WIDE_TORQUE_GAIN)),
    "procedural_torque_wide": ("climbs_procedural_torque_wide.npz", TRAINING_SEED + 1_800_000,
                               ClimbDraws(shapes="procedural", **WIDE_TORQUE_GAIN)),
    # both departures at once: the torque gain at +-15 % with the noise at 0-3 times the full scale and the lag at
    # 0-0.1 s (session 49, rule 78): the climbs of a train whose sensors are worse than the draws in more than one way
    "noisy_torque_wide": ("climbs_noisy_torque_wide.npz", TRAINING_SEED + 1_900_000,
                          ClimbDraws(**PAST_DRAWS_NOISE_AND_LAG, **WIDE_TORQUE_GAIN)),
    "procedural_noisy_torque_wide": ("climbs_procedural_noisy_torque_wide.npz", TRAINING_SEED + 2_000_000,
                                     ClimbDraws(shapes="procedural", **PAST_DRAWS_NOISE_AND_LAG, **WIDE_TORQUE_GAIN)),
    # the recipe's climbs with the encoder's speed signal lagged 0-20 ms per climb (v2 draws none; session 60: the
    # data for a filter and guards that have met a smoothed encoder; seeds from 3 300 000 and 3 400 000, those from
    # 3 100 000 and 3 200 000 being train_estimator.py's on-policy encoder collections)
    "torque_wide_encoder": ("climbs_torque_wide_encoder.npz", TRAINING_SEED + 2_300_000,
                            ClimbDraws(**WIDE_TORQUE_GAIN, encoder_lags_s=ENCODER_LAGS_S)),
    "procedural_torque_wide_encoder": ("climbs_procedural_torque_wide_encoder.npz", TRAINING_SEED + 2_400_000,
                                       ClimbDraws(shapes="procedural", **WIDE_TORQUE_GAIN,
                                                  encoder_lags_s=ENCODER_LAGS_S)),
    # the recipe's procedural climbs with peaks anywhere up to the env's largest drawn peak creepage (0.3-20 %
    # log-uniform: training.FAR_PEAK_CREEPAGE; the recipe's peak at 0.3-4 %): curves that still rise far past their
    # knee, where the shipped networks stop at a third of the saturation torque (session 70, docs/interrogator.md)
    "procedural_far_torque_wide": ("climbs_procedural_far_torque_wide.npz", TRAINING_SEED + 2_500_000,
                                   ClimbDraws(shapes="procedural", peak_creepages=FAR_PEAK_CREEPAGE,
                                              **WIDE_TORQUE_GAIN)),
}
# the shipped recipe (procedural and high_frequency lost on validation: README): since session 48 (rule 74) the env's
# draws with the torque gain anywhere within +-15 %, read calibrated by the torque balance (RECIPE_BALANCE_LAG_DEG)
EPISODES = {"torque_wide": 8000}
# the shipped recipe's guard (--guard-climbs; session 16): the family climbs and the procedural ones together (since
# session 48, rule 74, both with the wide torque gain)
GUARD_EPISODES = {"torque_wide": 8000, "procedural_torque_wide": 8000}
VALIDATION = HERE / "suites" / "v2_validation_grid.json"  # the v2 draws (families, sensor errors)
# procedural creep curves beyond every family, none of the held-out shapes: the selection's robustness data
PROCEDURAL_VALIDATION = HERE / "suites" / "v2_validation_procedural_grid.json"
# procedural creep curves with steep falling branches: crest_tradeoff.py's data (not the recipe's selection)
STEEP_VALIDATION = HERE / "suites" / "v2_validation_steep_grid.json"
PROBES = ((0.0, 0.1, False), (0.03, 0.08, False), (0.03, 0.08, True))  # (creep step, while std, sticky)


def climb_grid(targets, approaches=(None,), probes=PROBES, floors=(None,), untils=(None,), cautions=(1.5, 2.0),
               tone2s=(None,)) -> list[dict]:
    """Climbs at a 40 % modulation: target headroom x caution x largest step (0.15, 0.25) x
    ``approach_fraction`` x slow probe x ``floor_margin`` x ``creep_until`` (only where the probe creeps)
    x tone 2's (frequency Hz, weight) of a two-tone excitation; None: the key left out (the default)."""
    grid = []
    for h, c, m, a, (k, w, sticky), f, u, t in itertools.product(targets, cautions, (0.15, 0.25), approaches, probes,
                                                                 floors, untils, tone2s):
        if u is not None and k == 0.0:
            continue
        grid.append({"amplitude_ratio": 0.4, "target_headroom": h, "caution": c, "max_log_step": m,
                     **({} if a is None else {"approach_fraction": a}),
                     "creep_log_step": k, "creep_while_std": w, "creep_sticky": sticky,
                     **({} if f is None else {"floor_margin": f}), **({} if u is None else {"creep_until": u}),
                     **({} if t is None else {"tone2_frequency_hz": t[0], "tone2_weight": t[1]})})
    return grid


def grid_columns(climbs: list[dict]) -> list[str]:
    """The climb parameters a grid sets, in order of first appearance (a key may be left out of some)."""
    return list(dict.fromkeys(k for c in climbs for k in c))


GRIDS = {  # the climbs the selection tries
    # the recipe (session 9): session 8's climbs, and with the floor jump a slow probe that ends where
    # the predicted headroom is 0.12 or not (64 climbs)
    "recipe": climb_grid((0.07, 0.1)) + climb_grid((0.07, 0.1), floors=(0.2,), untils=(None, 0.12)),
    "session8": climb_grid((0.07, 0.1)),  # the recipe until session 8 (24 climbs)
    # the recipe's climbs with the floor jump and the slow probe's end, the shipped climb's structure (16 climbs):
    # the selection of networks fitted on task v3 (session 87), whose plays cost about 2.6 times the v2 wagon's
    "floor_until": climb_grid((0.07, 0.1), floors=(0.2,), untils=(0.12,)),
    # tried in session 8 and not adopted (README: its choice macro-slips in 15 of the 48 held-out episodes)
    "extended": climb_grid((0.07, 0.1, 0.15), approaches=(0.0, 0.3), probes=(PROBES[0], PROBES[2])),
    # tried in session 9 with networks fitted on env=8000 floor_jump=8000, not adopted (README)
    "floor": climb_grid((0.07, 0.1), floors=(None, 0.2)),
    # for networks fitted on two-tone climbs (--climbs two_tone=N, session 11): the recipe's winning
    # structure (caution 2, the sticky slow probe, the floor jump, with and without its end) x tone 2 at
    # 12 or 17 Hz with a weight of 0.5 or 1 (32 climbs)
    "two_tone": climb_grid((0.07, 0.1), probes=(PROBES[2],), floors=(0.2,), untils=(None, 0.12), cautions=(2.0,),
                           tone2s=((12.0, 0.5), (12.0, 1.0), (17.0, 0.5), (17.0, 1.0))),
}
# what is reported does not change the climb, so every estimate source is scored on the same episodes
ESTIMATES = [{"estimate_from": "filter", "best_coa_factor": 1.0}] + [
    {"estimate_from": "best_coa", "best_coa_factor": f} for f in (1.0, 1.02, 1.05)]


def cache_file(file: str, env_id: str = ENV_ID) -> str:
    """A collection's cache file name in OUT for climbs on ``env_id``: :data:`COLLECTIONS`' own on the v2 wagon, the
    id's version added before the suffix on another (``climbs_torque_wide_v3.npz``), so that no run reads another
    id's climbs as its own."""
    if env_id == ENV_ID:
        return file
    stem, _, suffix = file.rpartition(".")
    return f"{stem}_v{env_id.rpartition('-v')[2]}.{suffix}"


def load_or_collect(out: Path, name: str, episodes: int, workers: int, balance: bool = False,
                    env_id: str = ENV_ID) -> Dataset:
    """``episodes`` training climbs of collection ``name`` (:data:`COLLECTIONS`) on ``env_id``, from OUT's cache
    when it holds them (with ``balance``, recorded with each window's torque balance)."""
    file, first_seed, draws = COLLECTIONS[name]
    path = out / cache_file(file, env_id)
    if path.is_file():
        try:
            data = Dataset.load(path)
        except (ValueError, KeyError):
            data = None
        if data is not None and int(data.episode.max()) + 1 >= episodes and (data.reads_torque_balance or not balance):
            return data.subset(data.episode < episodes)
    t0 = time.time()
    data = collect_parallel(env_id, CONFIGS, episodes, workers, first_seed, draws)
    data.save(path)
    print(f"collected {episodes} {name} climbs on {env_id} ({len(data)} windows) in {time.time() - t0:.0f} s",
          flush=True)
    return data


def parse_climbs(parser: argparse.ArgumentParser, items: list[str], option: str = "--climbs",
                 collections: dict = COLLECTIONS) -> dict[str, int]:
    """``NAME=N`` items as {collection: climbs} (NAME a key of ``collections``); a bad item is a one-line usage
    error (exit 2) naming ``option``."""
    out = {}
    for item in items:
        name, _, n = item.partition("=")
        if name not in collections or not (n.isascii() and n.isdigit()):  # int() refuses "²", which isdigit() admits
            parser.error(f"{option}: expected NAME=N with NAME one of {', '.join(collections)} and N >= 0, got {item!r}")
        out[name] = int(n)
    if not any(out.values()):
        parser.error(f"{option}: at least one collection needs N > 0")
    return out


def collect(out: Path, climbs: dict[str, int], workers: int, balance: bool = False, env_id: str = ENV_ID) -> Dataset:
    """The training climbs of ``climbs`` ({collection: climbs}) on ``env_id``, in that order, from OUT's caches or
    collected (with ``balance``, caches recorded with the torque balance: :func:`load_or_collect`)."""
    return Dataset.concatenate([load_or_collect(out, name, n, workers, balance, env_id)
                                for name, n in climbs.items() if n])


def load_added_climbs(parser: argparse.ArgumentParser, files: list[Path], option: str = "--add-climbs") -> list[Dataset]:
    """The climbs of ``option`` (files a ``Dataset.save`` wrote); a missing or unreadable file is a one-line
    usage error (exit 2) naming the option, before any climb is collected or fitted."""
    return [load_climbs(parser, option, file) for file in files]


def split(data: Dataset, every: int = 10) -> tuple[Dataset, Dataset]:
    """Every ``every``-th episode apart (of every collection alike), to report the fit's held-out likelihood."""
    held = data.episode % every == every - 1
    return data.subset(~held), data.subset(held)


def episodes(run_dir: str, suite_path: str, env_kwargs: dict, params: dict | None = None,
             guards: list[str] | None = None, estimators: list[str] | None = None, scenario: dict | None = None,
             wrap=None, env_id: str | None = None):
    """(record, agent after the episode) of every episode of a suite (the default suite: 60 episodes)
    in a vehicle configuration, played by the interrogator of ``run_dir`` (``params``: another climb,
    ``guards`` / ``estimators``: other guard / estimator directories than its manifest's; ``scenario``: reset
    options over every episode's own, e.g. ``{"noise_level": 3.0}``; ``wrap``: what plays in its place, made from
    it, e.g. a recorder of its windows; ``env_id``: the suite played on that id, its episodes kept)."""
    suite = make_suite(suite_path, 60, 0)
    if env_id is not None and env_id != suite.env_id:
        suite = with_env_id(suite, env_id)
    climb = ClimbParameters(**params) if params else None
    options = (climb or manifest_climb(Path(run_dir))).env_options
    env = gym.make(suite.env_id, **{**suite.env_kwargs, **env_kwargs, **options})
    agent = interrogator_for(env, Path(run_dir), climb, None if guards is None else [Path(g) for g in guards],
                             None if estimators is None else [Path(e) for e in estimators])
    agent = agent if wrap is None else wrap(agent)
    for i, (seed, options) in enumerate(suite.episodes):
        yield run_episode(env, agent, seed, {**options, **(scenario or {})}, i), agent
    env.close()


def play(ensemble_dir: str, params: dict, suite_path: str, env_kwargs: dict,
         guards: list[str] | None = None, env_id: str | None = None) -> list[list[tuple[float, bool]]]:
    """(relative error, macro-slip) of every episode of a suite file, in a vehicle configuration, for
    each estimate source of ESTIMATES (``guards``: the climb's guard directories, None: the manifest's; ``env_id``:
    the suite played on that id)."""
    out: list[list[tuple[float, bool]]] = [[] for _ in ESTIMATES]
    for r, agent in episodes(ensemble_dir, suite_path, env_kwargs, params, guards, [],  # no estimator: ESTIMATES
                             env_id=env_id):
        for k, e in enumerate(ESTIMATES):
            out[k].append((source_error(agent, r, e["estimate_from"], e["best_coa_factor"]), r.macro_slip))
    return out


def source_error(agent, record, estimate_from: str, best_coa_factor: float = 1.0) -> float:
    """The relative CoF error the episode ``record`` of ``agent`` would have had with the estimate from
    ``estimate_from`` (the trajectory does not depend on it), clipped as the agent clips its action; 1.0
    where the episode is unscored."""
    limits = agent.limits
    estimate = agent.candidate_estimates(best_coa_factor)[estimate_from]
    estimate = limits.clip_estimate(estimate)
    return abs(estimate / record.cof - 1.0) if record.scored else 1.0


def score(results: list[tuple[float, bool]]) -> dict:
    return error_summary([e for e, _ in results], [s for _, s in results])


GUARDED_ESTIMATE = "guard"  # the estimate source of a guarded filter (rule 46, session 32; rules 44 and 16 before)
CREST_FLOOR = True  # the chosen climb's estimate at least its best crest bound (rule 21, session 22)
RUNAWAY_ESTIMATE = True  # between stops, the chosen climb reports what a runaway would (rule 23, session 23)
CREST_CEILING = True  # once the crest falls under a rising torque crest, the estimate at most it (rule 28, session 25)
CEILING_STOP = True  # ... and the climb ends at that window (rule 30's stop, adopted with rule 42, session 30)
# ... a fall counting only beyond 2 standard errors where the predicted headroom is above 0.5 (rule 50, session 33)
CEILING_FALL_Z, CEILING_NEAR_HEADROOM = 2.0, 0.5
# ... and the climb following the speed noise its first windows read beyond 0.4 N m s (rule 53, session 35)
NOISE_REFERENCE_NMS, NOISE_CAUTION_EXPONENT, NOISE_CREEP_EXPONENT = 0.4, 0.2, 0.85
# ... and every torque reading calibrated by the first window's torque balance where its lag is at most 65 deg
# (rules 70-71, session 46)
TORQUE_BALANCE, TORQUE_BALANCE_MAX_LAG_DEG = True, 65.0
# the recipe fits every network on the readings that climb reads, calibrated alike (--torque-balance-lag; rule 74,
# session 48)
RECIPE_BALANCE_LAG_DEG = TORQUE_BALANCE_MAX_LAG_DEG if TORQUE_BALANCE else None
# the slow probe stays slow once it has crept (rule 74, session 48): the rule confirmed the networks fitted on the
# wide torque gain with the climb shipped then, whose probe is sticky; the selection, which plays the filter alone
# without the parts below, ranks the probe that is not sticky first for them (pooled P90 25.1 % against 27.0 %, but
# 14 against 6 runaways on the procedural grid: docs/interrogator.md, rule 74)
CREEP_STICKY = True
# ... unless the cautious headroom is above 0.45 again: a probe started far below the peak climbs on (rule 94,
# session 53)
CREEP_RELEASE = 0.45
# the climb's parts the recipe sets after its selection (the adopted rules' constants above), by ClimbParameters field
ADOPTED_CLIMB = {"creep_sticky": CREEP_STICKY, "creep_release": CREEP_RELEASE, "crest_floor": CREST_FLOOR,
                 "runaway_estimate": RUNAWAY_ESTIMATE, "crest_ceiling": CREST_CEILING, "ceiling_stop": CEILING_STOP,
                 "ceiling_fall_z": CEILING_FALL_Z, "ceiling_near_headroom": CEILING_NEAR_HEADROOM,
                 "noise_reference_nms": NOISE_REFERENCE_NMS, "noise_caution_exponent": NOISE_CAUTION_EXPONENT,
                 "noise_creep_exponent": NOISE_CREEP_EXPONENT, "torque_balance": TORQUE_BALANCE,
                 "torque_balance_max_lag_deg": TORQUE_BALANCE_MAX_LAG_DEG}
CRITERIA = {  # how the selection ranks the climbs (sort keys of a table row)
    "pooled": lambda r: (r["macro_slips"], r["pooled_p90"], r["pooled_median"]),  # the recipe
    "family": lambda r: (r["macro_slips"], r["p90"], r["median"]),  # the family grid alone
}


def select_climb(ensemble_dir: Path, workers: int, criterion: str = "pooled",
                 grid: str = "recipe", guards: list[str] | None = None,
                 env_id: str | None = None) -> tuple[dict, list[dict]]:
    """The climb of GRIDS[grid] x ESTIMATES chosen on the two validation grids, both vehicle configurations;
    ``pooled`` (the recipe): fewest macro-slips on the family grid (VALIDATION), then, over both grids
    pooled with a macro-slip counted as a failed measurement (100 % error), the lowest P90, then median;
    ``family``: macro-slips, P90, median on the family grid alone. Every climb with the guard
    directories ``guards`` (None: the manifest's), the grids played on ``env_id`` (None: their own). Returns it
    and the whole table."""
    grids = [VALIDATION, PROCEDURAL_VALIDATION]
    climbs = GRIDS[grid]
    jobs = [(str(ensemble_dir), g, str(v), c, guards, env_id) for g in climbs for v in grids for c in CONFIGS]
    with ProcessPoolExecutor(workers) as pool:
        results = iter(list(pool.map(play, *zip(*jobs))))
    table = []
    for g in climbs:
        runs = [next(results) for _ in grids for _ in CONFIGS]
        family, procedural = runs[:len(CONFIGS)], runs[len(CONFIGS):]
        for j, e in enumerate(ESTIMATES):
            fam = [r for run in family for r in run[j]]
            proc = [r for run in procedural for r in run[j]]
            failed = score([(1.0 if slip else err, slip) for err, slip in fam + proc])  # a macro-slip: 100 %
            table.append({**g, **e, **score(fam), **{f"procedural_{k}": v for k, v in score(proc).items()},
                          "pooled_p90": failed["p90"], "pooled_median": failed["median"]})
    table.sort(key=CRITERIA[criterion])
    return {k: table[0][k] for k in (*grid_columns(climbs), *ESTIMATES[0]) if k in table[0]}, table


NOTHING_HELD_APART = "no climb held apart (fewer than 10 climbs)"  # a held-apart report of no window, not NaN




def lag_or_none(text: str) -> float | None:
    """An argparse type for ``--torque-balance-lag``: a window lag bound in (0, 90] deg, or ``none``."""
    if text == "none":
        return None
    try:
        return float_in_range(0.0, 90.0)(text)
    except argparse.ArgumentTypeError as error:  # float_in_range's "must be a finite number in (0, 90], got ..."
        raise argparse.ArgumentTypeError(f"must be 'none' or {str(error).removeprefix('must be ')}") from None


def file_digest(path: Path) -> str:
    """The first 12 hex digits of the SHA-256 of a file's bytes."""
    return hashlib.sha256(path.read_bytes()).hexdigest()[:12]


def training_record(climbs: dict[str, int], added: list[Path], settings: FitSettings,
                    balance_lag_deg: float | None = None, env_id: str = ENV_ID) -> dict:
    """What networks are fitted on, as JSON: the collections' climbs, each added climbs file's digest
    (its bytes, whatever its name or place), the fit settings, where the readings were calibrated by the
    torque balance (``--torque-balance-lag``), that window lag bound, and the id the climbs were collected on where
    it is not the v2 wagon (whose records name none)."""
    record = {"climbs": climbs, "added_sha256": [file_digest(f) for f in added], "fit": asdict(settings)}
    if env_id != ENV_ID:
        record["env_id"] = env_id
    if balance_lag_deg is not None:
        record["torque_balance_max_lag_deg"] = balance_lag_deg
    return json.loads(json.dumps(record))  # tuples as lists, as the file holds them


def stale_networks(out: Path, record: dict) -> bool:
    """Whether OUT's networks were fitted on other climbs or settings than ``record`` (OUT/training.json says
    so; a directory without it, from before session 30, counts as fitted on them)."""
    path = out / TRAINING_RECORD
    return path.is_file() and json.loads(path.read_text()) != record


def fit_networks(out: Path, load_data: Callable[[], Dataset], seeds: list[int], settings: FitSettings,
                 reuse: bool, record: dict | None = None) -> dict:
    """One filter network per seed on the climbs ``load_data()`` returns (every tenth climb held apart) in
    OUT/seed_K/member_0.npz, all of them in OUT/ensemble/member_K.npz; ``reuse``: a seed's network that
    exists is kept, and where every seed's exists no climb is loaded or collected (selection and report
    only: the held-apart likelihoods are not recomputed), unless OUT's ``record`` of what they were fitted
    on (:func:`training_record`, written to OUT/training.json) differs: then every seed is fitted again.
    Returns the held-apart likelihood per seed and of the ensemble."""
    ensemble_dir = out / "ensemble"
    ensemble_dir.mkdir(parents=True, exist_ok=True)
    if reuse and record is not None and stale_networks(out, record):
        print(f"{out.name}: its networks were fitted on other climbs or settings ({out / TRAINING_RECORD}): "
              "fitted again", flush=True)
        reuse = False
    kept = {seed: out / f"seed_{seed}" / "member_0.npz" for seed in seeds}
    if reuse and all(path.is_file() for path in kept.values()):
        members = {seed: FilterNetwork.load(path) for seed, path in kept.items()}
        fit_report = {"reused": "every seed's network kept; no climbs loaded, held-apart likelihoods not recomputed"}
    else:
        train, held = split(load_data())
        score = (lambda networks: nll(networks, held)) if len(held) else (lambda networks: NOTHING_HELD_APART)
        members, fit_report = {}, {}
        for seed in seeds:
            t = time.time()
            if reuse and kept[seed].is_file():
                members[seed] = FilterNetwork.load(kept[seed])
            else:
                members[seed] = fit_member(train, seed, settings)
                kept[seed].parent.mkdir(parents=True, exist_ok=True)
                members[seed].save(kept[seed])
                print(f"{out.name} seed {seed}: fitted in {time.time() - t:.0f} s", flush=True)
            fit_report[f"seed_{seed}"] = score(members[seed])
    if record is not None:
        (out / TRAINING_RECORD).write_text(json.dumps(record, indent=1) + "\n")
    for seed, member in members.items():
        member.save(ensemble_dir / f"member_{seed}.npz")
    if "reused" not in fit_report:
        fit_report["ensemble"] = score(FilterEnsemble.load(ensemble_dir))
    print(f"{out.name} held-out {fit_report}", flush=True)
    for stale in member_files(ensemble_dir):
        if int(stale.stem.split("_")[1]) not in seeds:
            stale.unlink()
    return fit_report


def require_networks(parser: argparse.ArgumentParser, option: str, directories: list[Path]) -> None:
    """A one-line usage error (exit 2) naming ``option`` for the first directory without networks
    (``member_*.npz``)."""
    for directory in directories:
        if not member_files(directory):
            parser.error(f"{option}: no networks (member_*.npz) in {directory}")


def install_guards(run: Path, guards: list[Path]) -> list[str]:
    """Copies the guard networks ``guards`` into ``run`` (``guard_K``, replacing any there) and returns
    their names, relative to ``run`` as its manifest names them."""
    for stale in run.glob("guard_*"):
        shutil.rmtree(stale)
    names = [f"guard_{k}" for k in range(len(guards))]
    for name, guard in zip(names, guards):
        copy_networks(guard, run / name)
    return names


def copy_networks(source: Path, target: Path) -> None:
    """The networks of ``source`` (``member_*.npz``) copied into the new directory ``target`` (its parents made)."""
    target.mkdir(parents=True)
    for member in ensemble_files(source):
        shutil.copy2(member, target / member.name)


def report_runs(runs: list[Path], workers: int, env_id: str | None = None) -> dict:
    """Every run (seed or ensemble) on the default suite, the held-out grids and the procedural
    validation grid (per seed: the selection played the ensemble there), per episode; each played on ``env_id``
    (None: the suite's own)."""
    suites = [{"name": "default", "path": "default"},
              *({"name": label, "path": str(HERE / "suites" / f"{name}.json")} for name, label in v2_heldout_grids().items()),
              {"name": "procedural validation grid (selection data, per seed)", "path": str(PROCEDURAL_VALIDATION)}]
    report = {}
    for s in suites:
        suite = make_suite(s["path"], 60, 0)
        jobs = [(str(r), s["path"], env_id) for r in runs]
        with ProcessPoolExecutor(workers) as pool:
            per_run = list(pool.map(_play_shipped_climb, *zip(*jobs)))
        report[s["name"]] = {"episodes": len(suite.episodes),
                             "runs": {r.name: {**score(res), "errors": [e for e, _ in res]} for r, res in zip(runs, per_run)}}
    return report


# a copy of a policy directory without its calibrated interval, which belongs to the shipped networks alone
WITHOUT_INTERVAL = shutil.ignore_patterns(INTERVAL_FILE)


def shipped_runs(out: Path, package: Path = SHIPPED_INTERROGATOR) -> list[Path]:
    """The shipped agent laid out as the recipe's runs (step 4's input): OUT/seed_K holds the package's
    ``member_J.npz`` of the manifest's J-th training seed K alone, OUT/ensemble every member; each has the
    package's guards (every member: the recipe copies the guards' ensembles into every run) and manifest."""
    seeds = json.loads((package / MANIFEST_FILE).read_text())["training"]["seeds"]
    members = member_files(package)
    if len(members) != len(seeds):
        raise ValueError(f"{package}: {len(members)} member_*.npz for the manifest's {len(seeds)} training seeds")
    runs = [out / f"seed_{s}" for s in seeds] + [out / "ensemble"]
    for run in runs:
        if run.exists():
            shutil.rmtree(run)
    # the calibrated interval belongs to the shipped networks alone: estimate_interval.py --write after a --ship
    shutil.copytree(package, runs[-1], ignore=WITHOUT_INTERVAL)
    for k, run in enumerate(runs[:-1]):
        shutil.copytree(package, run, ignore=lambda folder, names: [n for n in names if Path(folder) == package
                                                                     and (n.startswith("member_") or n == INTERVAL_FILE)])
        shutil.copy2(package / f"member_{k}.npz", run / "member_0.npz")
    return runs


def _play_shipped_climb(run_dir: str, suite_path: str, env_id: str | None = None) -> list[tuple[float, bool]]:
    return [(r.relative_error if r.scored else 1.0, r.macro_slip)
            for r, _ in episodes(run_dir, suite_path, {}, env_id=env_id)]


def markdown(report: dict, seeds: list[str]) -> str:
    lines = []
    for suite, block in report.items():
        lines += [f"### {suite} ({block['episodes']} episodes)", "",
                  "| run | median | P90 | macro-slips |", "|---|---|---|---|"]
        for name, r in block["runs"].items():
            lines.append(f"| {name} | {100 * r['median']:.1f} % | {100 * r['p90']:.1f} % | {r['macro_slips']} |")
        scores = np.array([block["runs"][s]["errors"] for s in seeds])
        lo, hi = stratified_bootstrap_ci(scores, iqm)
        mlo, mhi = stratified_bootstrap_ci(scores, np.median)
        lines += ["", f"Over {len(seeds)} seeds x {scores.shape[1]} scenarios: IQM {100 * iqm(scores):.1f} % "
                  f"[{100 * lo:.1f}, {100 * hi:.1f}], median {100 * np.median(scores):.1f} % "
                  f"[{100 * mlo:.1f}, {100 * mhi:.1f}] (stratified bootstrap 95 % CI).", ""]
    return "\n".join(lines)


def played_on(env_id: str, trained: bool = True) -> str:
    """The reports' sentence on the id every suite was played on (and, for a run that trains, ``trained``, every
    climb collected on): none on the v2 wagon, the suites' own."""
    if env_id == ENV_ID:
        return ""
    what = "Climbs collected and every suite (validation grids, report)" if trained else "Every suite"
    return f" {what} played on `{env_id}`, each suite's episodes kept."


def report_only(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """``--report-only``: the report (step 4) of the agent shipped for ``--env``, every seed and the ensemble, written
    to OUT/report.md and OUT/report.json; every option that fits, selects or ships is refused."""
    for option in ("ship", "reuse", "fit_only", "probing_guard"):
        if getattr(args, option):
            parser.error(f"--report-only: plays the shipped agent as it is, without --{option.replace('_', '-')}")
    for option in ("add_climbs", "add_guard_climbs", "guards"):
        if getattr(args, option):
            parser.error(f"--report-only: plays the shipped agent's own networks, without --{option.replace('_', '-')}")
    for option in ("climbs", "guard_climbs", "epochs", "loss", "features", "criterion", "grid", "seeds"):
        if getattr(args, option, None) != parser.get_default(option):  # what only fitting or selecting reads
            parser.error(f"--report-only: fits and selects nothing, so --{option.replace('_', '-')} would be ignored")
    t0 = time.time()
    args.out.mkdir(parents=True, exist_ok=True)
    runs = shipped_runs(args.out, SHIPPED_INTERROGATORS[args.env])
    report = report_runs(runs, args.workers, args.env)
    text = ["# Learned interrogator: the shipped agent per seed", "",
            f"Command: `python experiments/train_interrogator.py {' '.join(sys.argv[1:])}` ({time.time() - t0:.0f} s on "
            "this machine; the shipped networks, guards and climb, nothing fitted or selected)."
            + played_on(args.env, trained=False),
            "",
            markdown(report, [r.name for r in runs[:-1]])]
    (args.out / "report.md").write_text("\n".join(text) + "\n")
    (args.out / "report.json").write_text(json.dumps({"report": report}, indent=1))
    print("\n".join(text))


MODEL_CARD = "README.md"  # the shipped package's card: written by hand, kept by a ship


def ship(ensemble_dir: Path, package: Path = SHIPPED_INTERROGATOR) -> None:
    """``ensemble_dir`` (networks, guards, manifest) becomes the shipped package; its model card stays, and no
    interval is left (estimate_interval.py --write calibrates the new networks')."""
    card = (package / MODEL_CARD).read_text() if (package / MODEL_CARD).is_file() else None
    if package.exists():
        shutil.rmtree(package)
    shutil.copytree(ensemble_dir, package, ignore=WITHOUT_INTERVAL)
    if card is not None:
        (package / MODEL_CARD).write_text(card)


def build_parser() -> Parser:
    """The recipe's options."""
    ap = Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("runs/interrogator"))
    ap.add_argument("--climbs", nargs="+", default=[f"{k}={v}" for k, v in EPISODES.items()], metavar="NAME=N",
                    help=f"training climbs per collection ({', '.join(COLLECTIONS)}; 0 or absent: none)")
    ap.add_argument("--seeds", type=seed_int, nargs="+", default=[0, 1, 2, 3, 4], action=DistinctValues)
    ap.add_argument("--workers", type=positive_int, default=2)
    ap.add_argument("--epochs", type=int, default=FitSettings.epochs)
    ap.add_argument("--loss", choices=FIT_LOSSES, default=FitSettings.loss,
                    help="the likelihood the networks are fitted under: gaussian (the recipe: each output's conditional "
                         "mean) or laplace (its conditional median); default: %(default)s")
    ap.add_argument("--features", nargs="*", default=[], choices=FITTABLE_BLOCKS,
                    help="optional feature blocks the networks read (tone 2's follow two-tone climbs; torque_free "
                         "leaves out every feature of the compliance, which reads the torque sensor's gain; "
                         "applied_amplitude reads the applied modulation ratio in place of the commanded one)")
    ap.add_argument("--ship", action="store_true")
    ap.add_argument("--criterion", choices=sorted(CRITERIA), default="pooled",
                    help="how the climb is ranked on validation (pooled: both grids, the recipe; family: the family "
                         "grid alone)")
    ap.add_argument("--grid", choices=sorted(GRIDS), default="recipe", help="the climbs tried (recipe: the shipped recipe's)")
    ap.add_argument("--reuse", action="store_true",
                    help="keep OUT/seed_K networks that exist (selection and report only; where every seed's network "
                         "exists, filter's and guard's, no climb is loaded or collected)")
    ap.add_argument("--fit-only", action="store_true",
                    help="fit the networks and stop (no selection, report or manifest): networks for another run's "
                         "--guards or crest_tradeoff.py --run")
    ap.add_argument("--guard-climbs", nargs="+", default=[f"{k}={v}" for k, v in GUARD_EPISODES.items()] or ["none"],
                    metavar="NAME=N",
                    help="training climbs per collection of a guard fitted in OUT/guard/ (same seeds and fit) that steers "
                         "the climb beside the filter; 'none': no guard fitted (default: %(default)s)")
    ap.add_argument("--add-climbs", type=Path, nargs="+", default=[], metavar="FILE",
                    help="climbs recorded elsewhere (a Dataset file, e.g. train_estimator.py's on-policy cache) added "
                         "to the filter's training climbs (not the guard's)")
    ap.add_argument("--add-guard-climbs", type=Path, nargs="+", default=[], metavar="FILE",
                    help="climbs recorded elsewhere added to the guard's training climbs (with --guard-climbs)")
    ap.add_argument("--probing-guard", action="store_true",
                    help="with --add-guard-climbs, also a guard fitted on the --guard-climbs alone (OUT/probing_guard/: "
                         "the first step's guard), steering beside the one that learns the added climbs (rule 45)")
    ap.add_argument("--guards", type=Path, nargs="+", default=[], metavar="DIR",
                    help="networks (DIR/member_*.npz, e.g. another run's ensemble) that steer the climb beside the "
                         "filter as its guards: copied into every run directory, named in the manifest")
    ap.add_argument("--torque-balance-lag", type=lag_or_none, default=RECIPE_BALANCE_LAG_DEG, metavar="DEG",
                    help="fit every network on readings calibrated as a climb with torque_balance and "
                         "torque_balance_max_lag_deg=DEG reads them (Dataset.calibrated; caches recorded without the "
                         "balance are collected again, added climbs must hold it); 'none': the readings as read "
                         "(default: %(default)s, the shipped climb's bound)")
    ap.add_argument("--env", choices=TRAINING_ENV_IDS, default=ENV_ID,
                    help="the id the climbs are collected on and the validation grids and the report's suites played "
                         "on, their episodes kept (default: %(default)s, the shipped interrogator's; --ship writes "
                         "each id's own package)")
    ap.add_argument("--report-only", action="store_true",
                    help="step 4 alone, on the shipped agent as it is (its networks, guards and climb; OUT/seed_K: "
                         "member K alone): no climbs, no fit, no selection")
    return ap


@dataclass(frozen=True)
class TrainingClimbs:
    """What the networks are fitted on, as checked from the command line: the filter's collections and recorded
    climbs, the guard's (none: no guard is fitted), and whether every reading is calibrated by the torque balance."""

    filter_collections: dict[str, int]
    filter_added: list[Dataset]
    guard_collections: dict[str, int]
    guard_added: list[Dataset]
    balance: bool


def checked_climbs(ap: argparse.ArgumentParser, args: argparse.Namespace) -> TrainingClimbs:
    """The training climbs the options name, every option checked before any climb is collected (exit 2)."""
    require_networks(ap, "--guards", args.guards)
    climbs = parse_climbs(ap, args.climbs)
    guard_climbs = {} if args.guard_climbs == ["none"] else parse_climbs(ap, args.guard_climbs, "--guard-climbs")
    added = load_added_climbs(ap, args.add_climbs)
    if args.add_guard_climbs and not guard_climbs:
        ap.error("--add-guard-climbs: no guard is fitted (--guard-climbs none)")
    if args.probing_guard and not args.add_guard_climbs:
        ap.error("--probing-guard: needs --add-guard-climbs (without them OUT/guard/ is the probing guard)")
    added_to_guard = load_added_climbs(ap, args.add_guard_climbs, "--add-guard-climbs")
    balance = args.torque_balance_lag is not None
    added_files = (("--add-climbs", args.add_climbs, added),
                   ("--add-guard-climbs", args.add_guard_climbs, added_to_guard))
    for option, files, data in added_files if balance else ():
        for file, climbs_read in zip(files, data):
            if not climbs_read.reads_torque_balance:
                ap.error(f"{option}: {file} was recorded without the torque balance; --torque-balance-lag needs it")
    return TrainingClimbs(climbs, added, guard_climbs, added_to_guard, balance)


def fit_all(args: argparse.Namespace, training: TrainingClimbs, settings: FitSettings) -> tuple[dict, list[Path]]:
    """The filter's networks in OUT and, where asked, the guard's (OUT/guard/) and the probing guard's
    (OUT/probing_guard/), each recorded with what it was fitted on; returns the fit report and every guard that
    steers beside the filter (``--guards`` first)."""
    out = args.out

    def fit(directory: Path, collections: dict[str, int], files: list[Path], data: list[Dataset]) -> dict:
        """fit_networks in ``directory`` on the climbs of ``collections`` and those of ``files`` (``data``, read
        from them), recorded as such."""
        def load() -> Dataset:
            climbs_read = Dataset.concatenate([collect(out, collections, args.workers, training.balance, args.env),
                                               *data])
            return climbs_read.calibrated(args.torque_balance_lag) if training.balance else climbs_read

        return fit_networks(directory, load, args.seeds, settings, args.reuse,
                            training_record(collections, files, settings, args.torque_balance_lag, args.env))

    fit_report = fit(out, training.filter_collections, args.add_climbs, training.filter_added)
    guards = list(args.guards)
    if training.guard_collections:  # the recipe's guard: networks of their own, fitted alike on other climbs
        fit_report["guard"] = fit(out / "guard", training.guard_collections, args.add_guard_climbs,
                                  training.guard_added)
        guards.append(out / "guard" / "ensemble")
    if args.probing_guard:  # the first step's guard beside it (rule 45): fitted on the guard's climbs alone
        fit_report["probing_guard"] = fit(out / "probing_guard", training.guard_collections, [], [])
        guards.append(out / "probing_guard" / "ensemble")
    return fit_report, guards


def recipe_manifest(args: argparse.Namespace, training: TrainingClimbs, settings: FitSettings, chosen: dict,
                    guard_names: list[str]) -> dict:
    """Every run's manifest.json: the chosen climb over the defaults, the training distribution, what was fitted
    on what, and the guards' directories."""
    manifest = {"climb": {**asdict(ClimbParameters()), **chosen},
                "trained_on": {"env_id": args.env, "configs": CONFIGS},
                "training": {"climbs": training.filter_collections, "seeds": args.seeds, "fit": asdict(settings)}}
    if guard_names:
        manifest["guards"] = guard_names
    if training.guard_collections:
        manifest["training"]["guard_climbs"] = training.guard_collections
    if args.add_climbs:
        manifest["training"]["added_climbs"] = [str(f) for f in args.add_climbs]
    if args.add_guard_climbs:
        manifest["training"]["added_guard_climbs"] = [str(f) for f in args.add_guard_climbs]
    if training.balance:
        manifest["training"]["torque_balance_max_lag_deg"] = args.torque_balance_lag
    if args.probing_guard:
        manifest["training"]["probing_guard"] = guard_names[-1]  # fitted on the guard climbs alone
    return manifest


def selection_table(table: list[dict], columns: list[str], criterion: str) -> list[str]:
    """The selection's section of the report: how the climbs were ranked and the best 10 of them."""
    ranking = ("ranked by macro-slips on the first, then P90 and median over both with a macro-slip counted as 100 % "
               "error" if criterion == "pooled" else "ranked by macro-slips, P90, median on the first alone")
    lines = [f"## Climb selection ({VALIDATION.relative_to(HERE.parent)} and "
             f"{PROCEDURAL_VALIDATION.relative_to(HERE.parent)}, both vehicle configurations; {ranking}; the best 10 "
             "of the grid)", "",
             "| " + " | ".join(k.replace("_", " ") for k in columns) + " | estimate | family grid: median / P90 / "
             "macro-slips | procedural grid: median / P90 / macro-slips | pooled P90 (macro-slip = 100 %) |",
             "|---" * (len(columns) + 4) + "|"]
    lines += ["| " + " | ".join(str(r.get(k, "-")) for k in columns) + " | "
              f"{r['estimate_from'] if r['estimate_from'] == 'filter' else 'best CoA x %g' % r['best_coa_factor']} | "
              f"{100 * r['median']:.1f} % / {100 * r['p90']:.1f} % / {r['macro_slips']} | "
              f"{100 * r['procedural_median']:.1f} % / {100 * r['procedural_p90']:.1f} % / "
              f"{r['procedural_macro_slips']} | {100 * r['pooled_p90']:.1f} % |" for r in table[:10]]
    return lines


def shipped_estimate_text(chosen: dict) -> str:
    """The report's sentence on the shipped estimate: its source and every rule that bounds it or ends the climb."""
    why = (" (the guards' corrections pooled at every window: rule 46)"
           if chosen["estimate_from"] == GUARDED_ESTIMATE else "")
    why += (", at least the climb's best crest bound (the measured CoA's cycle crest less a bin's standard error: "
            "rule 21)" if chosen["crest_floor"] else "")
    why += ("; between stops, what a runaway in the coming window would measure (the middle of the best crest bound "
            "and the bound scaled by the coming torque crest: rule 23)" if chosen["runaway_estimate"] else "")
    why += ("; every estimate at most the best crest plus a bin's standard error once the crest has fallen under a "
            "rising torque crest (rule 28)" if chosen["crest_ceiling"] else "")
    why += ("; the climb ends at the window where the crest falls under a rising torque crest (rule 30's stop, "
            "rule 42)" if chosen["ceiling_stop"] else "")
    why += (f"; where the predicted headroom is above {chosen['ceiling_near_headroom']:g} a crest fall counts only beyond "
            f"{chosen['ceiling_fall_z']:g} standard errors of the two crests (rule 50)"
            if chosen["ceiling_near_headroom"] is not None and chosen["ceiling_fall_z"] > 0 else "")
    why += (f"; where the first windows read r times more speed noise than {chosen['noise_reference_nms']:g} N m s, the "
            f"cautions r^-{chosen['noise_caution_exponent']:g} and the slow probe's threshold "
            f"r^{chosen['noise_creep_exponent']:g} times the chosen ones (rule 53)"
            if chosen["noise_reference_nms"] is not None else "")
    return f"Shipped estimate: `{chosen['estimate_from']}`{why}."


def main() -> None:
    ap = build_parser()
    args = ap.parse_args()
    check_out_dir(ap, "--out", args.out)
    if args.epochs < 1:
        ap.error(f"--epochs must be at least 1, got {args.epochs}")
    if args.report_only:
        report_only(ap, args)
        return
    if args.ship and args.fit_only:
        ap.error("--ship: not with --fit-only, which stops before the selection whose climb ships")
    training = checked_climbs(ap, args)
    out = args.out
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.time()
    settings = replace(FitSettings(), epochs=args.epochs, features=tuple(args.features), loss=args.loss)
    ensemble_dir = out / "ensemble"
    fit_report, guards = fit_all(args, training, settings)
    if args.fit_only:
        return
    t = time.time()
    # the selection plays the filter with the --guards networks only (read where they are); the recipe's guard
    # joins the chosen climb, and every guard is copied into every run below
    chosen, table = select_climb(ensemble_dir, args.workers, args.criterion, args.grid, [str(g) for g in args.guards],
                                 args.env)
    print(f"climb selected on validation in {time.time() - t:.0f} s: {chosen}", flush=True)
    runs = [out / f"seed_{s}" for s in args.seeds] + [ensemble_dir]
    guard_names = [install_guards(r, guards) for r in runs][-1]  # the same names in every run
    if guard_names and chosen.get("estimate_from") == "filter":
        chosen = {**chosen, "estimate_from": GUARDED_ESTIMATE}
    chosen = {**chosen, **ADOPTED_CLIMB}
    manifest = recipe_manifest(args, training, settings, chosen, guard_names)
    for r in runs:
        write_manifest(r, manifest)
    report = report_runs(runs, args.workers, args.env)
    text = ["# Learned interrogator: seeds, selection and report", "",
            f"Command: `python experiments/train_interrogator.py {' '.join(sys.argv[1:])}` ({time.time() - t0:.0f} s on "
            f"this machine{'; networks reused, not fitted' if args.reuse else ''})." + played_on(args.env), "",
            *selection_table(table, grid_columns(GRIDS[args.grid]), args.criterion),
            "", shipped_estimate_text(chosen), "",
            "## Report (nothing chosen here)", "", markdown(report, [f"seed_{s}" for s in args.seeds])]
    (out / "report.md").write_text("\n".join(text) + "\n")
    (out / "report.json").write_text(json.dumps({"fit": fit_report, "selection": table, "report": report}, indent=1))
    print("\n".join(text))
    if args.ship:
        package = SHIPPED_INTERROGATORS[args.env]
        ship(ensemble_dir, package)
        print(f"shipped {ensemble_dir} -> {package}" + ("; calibrate its interval with python "
                                                        "experiments/estimate_interval.py --write" if args.env == ENV_ID
                                                        else ""))


if __name__ == "__main__":
    main()

"""Fit an interrogator's on-policy estimator (cof_gym/agents/interrogator.py, "Estimators"). 2 cores, CPU.

    python experiments/train_estimator.py --policy cof_gym/agents/policies/interrogator --out runs/estimator

1. **Data, on policy**: the interrogator of ``--policy`` (its networks, guards and climb, unchanged)
   climbs training episodes of the v2 wagon's randomisation, half with the paper's counter torque
   (:func:`cof_gym.agents.interrogator.training.collect` with ``policy``): the env's creep-law draws
   (seeds from 2 100 000 on) and procedural creep curves beyond every family (from 2 200 000 on), far
   from every evaluation seed and from the probing climbs' (ON_POLICY; ``--climbs NAME=N``, default
   4000 each; ``env_encoder`` and ``procedural_encoder``, from 3 100 000 and 3 200 000 on: the same with the
   encoder's speed signal lagged 0-20 ms, uniform per climb, rule 110). Every window is kept with its labels
   from the episode's truth. Cached in OUT/onpolicy_NAME_DIGEST.npz, the digest naming the policy's networks
   and climb; with ``--env CofGym/TorqueInterrogationInService-v3`` the climbs are those of task v3's wagon (a
   speed probe and an irregular track drawn; session 88), cached as OUT/onpolicy_NAME_DIGEST_v3.npz. ``--collect-only``
   stops here (a policy's own climbs for another fit: ``train_interrogator.py --add-climbs``). With
   ``--set NAME=VALUE ...`` the policy climbs with those climb parameters changed (a copy of it in
   OUT/policy/ whose manifest says so, e.g. ``--set ceiling_stop=false``: the recipe's first agent as it
   was shipped until session 30, whose climbs its guard learns; train_interrogator.py's docstring).
2. **Networks**: one per seed, fitted as the policy's filter was (its manifest's fit settings: a
   bootstrap resample of the episodes, Gaussian NLL, or with ``--loss laplace`` the Laplace NLL, whose
   location is the conditional median), every tenth episode held apart; OUT/seed_K/ and the ensemble
   OUT/ensemble/. The held-apart correction RMSE and mean absolute error at the window each climb's
   estimate reads (its last rising window) are printed beside the policy's filter's and guards' on the
   same windows.

The estimator never steers: it can change the reported estimate only, never a torque. Which estimate
source ships (``estimate_from``) is decided by a rule on the validation grids and a confirmation set
(docs/interrogator.md).
"""

from __future__ import annotations

import hashlib
import json
import shutil
import sys
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from crest_tradeoff import checked_climb, climb_item  # noqa: E402
from script_checks import check_out_dir  # noqa: E402
from train_interrogator import (  # noqa: E402
    CONFIGS, ENCODER_LAGS_S, ENV_ID, TRAINING_ENV_IDS, cache_file, fit_networks, parse_climbs, require_networks, split)

from cof_gym.agents.interrogator import (  # noqa: E402
    SHIPPED_INTERROGATOR, FilterEnsemble, manifest_climb, manifest_guards, manifest_networks, read_manifest,
    write_manifest,
)
from cof_gym.commands.args import DistinctNames, DistinctValues, Parser, positive_int, seed_int  # noqa: E402
from cof_gym.task.creep_fit import coa_fell  # noqa: E402
from cof_gym.agents.interrogator.networks import ensemble_files  # noqa: E402
from cof_gym.agents.policy_files import MANIFEST_FILE  # noqa: E402
from cof_gym.agents.interrogator.training import (  # noqa: E402
    FIT_LOSSES, FITTABLE_BLOCKS, READING_FIELDS, TRAINING_SEED, ClimbDraws, Dataset, FitSettings, collect_parallel,
)

# the on-policy collections: name -> (first seed, what the episodes draw beyond the env's own)
ON_POLICY = {"env": (TRAINING_SEED + 1_100_000, ClimbDraws()),
             "procedural": (TRAINING_SEED + 1_200_000, ClimbDraws(shapes="procedural")),
             # the same with the encoder's speed signal lagged (a time constant drawn per climb; v2 draws none)
             "env_encoder": (TRAINING_SEED + 2_100_000, ClimbDraws(encoder_lags_s=ENCODER_LAGS_S)),
             "procedural_encoder": (TRAINING_SEED + 2_200_000,
                                    ClimbDraws(shapes="procedural", encoder_lags_s=ENCODER_LAGS_S))}
EPISODES = {"env": 4000, "procedural": 4000}
REPORTING_ONLY = ("estimate_from", "best_coa_factor", "crest_floor", "runaway_estimate",
                  "crest_ceiling")  # change no torque of the climb


def policy_digest(policy: Path) -> str:
    """A short digest of what steers ``policy``'s climb: its manifest's climb (less what only picks the
    reported estimate) and every network that steers (filter and guards), so that a cache of its climbs is
    never read for another policy, and is read again where only the estimate changed."""
    climb = {k: v for k, v in asdict(manifest_climb(policy)).items() if k not in REPORTING_ONLY}  # defaults filled in
    h = hashlib.sha1(json.dumps(climb, sort_keys=True).encode())
    for directory in (policy, *manifest_guards(policy)):
        for member in ensemble_files(directory):
            h.update(member.read_bytes())
    return h.hexdigest()[:12]


def policy_with(policy: Path, changes: dict, out: Path) -> Path:
    """A copy of ``policy`` (networks, guards, manifest) in OUT/policy/, replacing any there, whose manifest's
    climb has the parameters ``changes``; ``policy`` itself where there are none."""
    if not changes:
        return policy
    copy = out / "policy"
    if copy.exists():
        shutil.rmtree(copy)
    shutil.copytree(policy, copy)
    manifest = read_manifest(copy)
    manifest["climb"] = {**manifest.get("climb", {}), **changes}
    write_manifest(copy, manifest)
    return copy


def collect_on_policy(policy: Path, out: Path, climbs: dict[str, int], workers: int, env_id: str = ENV_ID) -> Dataset:
    """``policy``'s own climbs of the :data:`ON_POLICY` collections (``climbs``: {name: episodes}) on ``env_id``, from
    OUT's cache when it holds them (a cache file per id: :func:`train_interrogator.cache_file`)."""
    digest, parts = policy_digest(policy), []
    for name, episodes in climbs.items():
        path = out / cache_file(f"onpolicy_{name}_{digest}.npz", env_id)
        cached = Dataset.load(path) if path.is_file() else None
        held = int(cached.episode.max()) + 1 if cached is not None and len(cached) else 0
        if held % len(CONFIGS):  # a cache that ends mid-rotation of the configurations is not extended
            cached, held = None, 0
        if held < episodes:  # the missing episodes only, in the same order (seeds, configurations)
            first_seed, draws = ON_POLICY[name]
            t0 = time.time()
            more = collect_parallel(env_id, CONFIGS, episodes - held, workers, first_seed + held, draws, str(policy))
            cached = Dataset.concatenate([cached, more]) if held else more
            out.mkdir(parents=True, exist_ok=True)
            cached.save(path)
            print(f"collected {episodes - held} on-policy {name} climbs on {env_id} ({len(more)} windows) in "
                  f"{time.time() - t0:.0f} s", flush=True)
        parts.append(cached.subset(cached.episode < episodes))
    return Dataset.concatenate(parts)


def estimate_windows(data: Dataset) -> np.ndarray:
    """The row of each episode whose correction the climb's estimate reads: its last window whose CoA did
    not fall (:func:`~cof_gym.task.creep_fit.coa_fell`, the agent's rule), the final window excluded (the
    window after the stop)."""
    coa = data.readings[:, READING_FIELDS.index("coa")]
    rows = []
    for e in np.unique(data.episode):
        idx = np.flatnonzero(data.episode == e)
        idx = idx[:-1] if len(idx) > 1 else idx
        rising = [i for k, i in enumerate(idx) if k == 0 or not coa_fell(coa[i], coa[idx[k - 1]])]
        rows.append(rising[-1])
    return np.asarray(rows)


def correction_residuals(networks: dict[str, Path], data: Dataset) -> dict[str, np.ndarray]:
    """Each ensemble's correction residual (target - prediction, log units) at ``data``'s estimate windows."""
    rows = estimate_windows(data)
    out = {}
    for name, directory in networks.items():
        ensemble = FilterEnsemble.load(directory)
        mean, _ = ensemble.predict(data.features_for(ensemble.blocks)[rows])
        out[name] = data.targets[rows, 1] - mean[:, 1]
    return out


def fit_estimator(policy: Path, out: Path, climbs: dict[str, int], seeds: list[int], workers: int,
                  reuse: bool, loss: str = "gaussian", features: tuple[str, ...] | None = None,
                  env_id: str = ENV_ID) -> dict:
    """Collect ``policy``'s climbs, fit one network per seed with its manifest's fit settings under
    ``loss`` (:data:`~cof_gym.agents.interrogator.training.FIT_LOSSES`; OUT/seed_K, OUT/ensemble), reading the
    feature blocks ``features`` where given (the manifest's otherwise), the climbs on ``env_id``, and return the fit's
    held-apart report, the estimate windows' correction RMSE and mean absolute error included."""
    fit = {k: tuple(v) if isinstance(v, list) else v
           for k, v in read_manifest(policy).get("training", {}).get("fit", {}).items()}
    settings = FitSettings(**{**fit, "loss": loss, **({} if features is None else {"features": tuple(features)})})
    data = collect_on_policy(policy, out, climbs, workers, env_id)
    report = fit_networks(out, lambda: data, seeds, settings, reuse)
    _, held = split(data)
    networks = {"estimator": out / "ensemble", "filter": policy,
                **{g.name: g for g in manifest_guards(policy)}}
    residuals = correction_residuals(networks, held)
    report["estimate_window_correction_rmse"] = {k: float(np.sqrt(np.mean(r**2))) for k, r in residuals.items()}
    report["estimate_window_correction_mae"] = {k: float(np.mean(np.abs(r))) for k, r in residuals.items()}
    report["settings"] = asdict(settings)
    print(f"held-apart correction RMSE and mean absolute error at the estimate windows: "
          f"{report['estimate_window_correction_rmse']}, {report['estimate_window_correction_mae']}", flush=True)
    return report


def main() -> None:
    ap = Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--policy", type=Path, default=SHIPPED_INTERROGATOR,
                    help="the interrogator whose climbs the estimator learns (a directory with member_*.npz and manifest.json)")
    ap.add_argument("--out", type=Path, default=Path("runs/estimator"))
    ap.add_argument("--climbs", nargs="+", default=[f"{k}={v}" for k, v in EPISODES.items()], metavar="NAME=N",
                    help=f"on-policy episodes per collection ({', '.join(ON_POLICY)}; default: %(default)s)")
    ap.add_argument("--seeds", type=seed_int, nargs="+", default=[0, 1, 2, 3, 4], action=DistinctValues)
    ap.add_argument("--env", choices=TRAINING_ENV_IDS, default=ENV_ID,
                    help="the id whose wagon the policy climbs (default: %(default)s, the shipped agent's)")
    ap.add_argument("--workers", type=positive_int, default=2)
    ap.add_argument("--reuse", action="store_true", help="keep OUT/seed_K networks that exist")
    ap.add_argument("--collect-only", action="store_true",
                    help="collect the policy's climbs into OUT's cache and stop (no networks, no report)")
    ap.add_argument("--set", nargs="+", default=[], metavar="NAME=VALUE", type=climb_item, action=DistinctNames,
                    help="the policy climbs with these climb parameters (ClimbParameters fields; values JSON or plain "
                         "text) changed: a copy of it in OUT/policy/")
    ap.add_argument("--loss", choices=FIT_LOSSES, default="gaussian",
                    help="the likelihood the networks are fitted under: gaussian (the conditional mean of the "
                         "correction) or laplace (its conditional median); default: %(default)s")
    ap.add_argument("--features", nargs="*", default=None, choices=FITTABLE_BLOCKS,
                    help="feature blocks the estimator reads besides the window's (default: the policy's fit's, its "
                         "manifest's training.fit.features; e.g. creepage_rise, rule 143)")
    args = ap.parse_args()
    check_out_dir(ap, "--out", args.out)
    require_networks(ap, "--policy", [args.policy])
    if not (args.policy / MANIFEST_FILE).is_file():
        ap.error(f"--policy: no manifest.json in {args.policy} (the climb the estimator learns)")
    try:  # the --set values against the policy's own climb
        checked_climb(read_manifest(args.policy).get("climb", {}), dict(args.set), len(manifest_guards(args.policy)),
                      len(manifest_networks(args.policy, "estimators")))
    except ValueError as error:
        ap.error(f"--set: {error}")
    climbs = parse_climbs(ap, args.climbs, "--climbs", ON_POLICY)
    t0 = time.time()
    policy = policy_with(args.policy, dict(args.set), args.out)
    if args.collect_only:
        data = collect_on_policy(policy, args.out, climbs, args.workers, args.env)
        print(f"{len(data)} windows of {len(np.unique(data.episode))} climbs in {args.out} in {time.time() - t0:.0f} s")
        return
    report = fit_estimator(policy, args.out, climbs, args.seeds, args.workers, args.reuse, args.loss, args.features,
                           args.env)
    (args.out / "report.json").write_text(json.dumps(report, indent=1) + "\n")
    print(f"done in {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()

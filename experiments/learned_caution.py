"""Reinforcement learning on top of the learned interrogator: a PPO policy that sets the climb's caution window by
window (run from the repository root; 2 cores, about 5 minutes a seed at 40 000 steps).

    python experiments/learned_caution.py --out runs/caution_rl --seeds 0 1 2 3 4 [--timesteps 40000]

The shipped interrogator steers its DC torque by the predicted headroom ``ln(M_sat / DC)`` less ``caution``
standard deviations (2, chosen on the validation grids; its guards likewise). Every rule since session 49 moved that
trade of accuracy against runaways by hand. Here PPO (stable-baselines3) learns it from the task's own return: its
action ``a`` in [-1, 1] sets the caution of the climb's next decision to ``2 exp(CAUTION_SPAN a)`` (1 ... 4 for the
filter and both guards), and its observation is what the climb decided after the last window
(``LearnedInterrogator.climb_state``: the filter's predicted headroom and std, the steering headroom and std, the
step taken, whether it has crept or stuck, the windows left, the noise it reads); no ground truth. At ``a = 0`` the climb is
the shipped one, action for action (tested), and PPO starts there (a mean of about 0, ``log_std_init``).

Training episodes (their own seeds, from ``TRAINING_SEED``, none shared with a validation or confirmation grid):
the v2 wagon's draws in both vehicle configurations, the creep curve from the env's families, from procedural
tables or from procedural tables with steep falling branches, a third each
(:func:`~cof_gym.agents.interrogator.training.procedural_shape`), the torque gain anywhere within +-15 %, and in one
episode of four the sensors' noise at 0-3 times the full scale and the drive's lag at 0-0.1 s: the four validation
plays' kinds, never their episodes. Each seed's model goes to ``OUT/seed_K/model.zip`` with ``training.json``.
``experiments/crest_tradeoff.py --caution-policy OUT/seed_K/model.zip`` plays it on any grid set, with the
records the rule checks read (:func:`steered`).

    python experiments/learned_caution.py --out runs/caution_lagrangian --seeds 0 1 2 3 4 --cost-budget 0.085

trains by PPO-Lagrangian instead (:func:`lagrangian`): the reward less a multiplier times the runaway cost, the
multiplier moved by dual ascent after each rollout so that at most ``--cost-budget`` runaways per episode are spent
(the budget above: the shipped climb's own share on ``--paired``'s episodes); ``training.json`` keeps the rollouts'
runaway rates and multipliers.

    python experiments/learned_caution.py --report PLAY [PLAY ...] --baseline PLAY --out out/learned_caution.md

reports the seeds' plays together (each PLAY: ``crest_tradeoff.py --records`` files of one seed joined by ``+``, the
same grids in the same order for every seed and the baseline): each seed's runaways, median, P90 and mean return,
and the interquartile mean of the relative error over seeds x climbs with its stratified-bootstrap 95 % CI (the
seeds resampled within each climb, as rliable does; ``ppo_seeds.py``'s), beside the baseline's.

    python experiments/learned_caution.py --paired runs/caution_rl/seed_0/model.zip [--episodes 60]

plays a model and the shipped climb on the same held-apart training-draw episodes (``--episodes`` per vehicle
configuration, outer seeds from ``PAIRED_SEED``) and prints both mean returns and runaways and the returns' paired
difference with its standard error: what the training distribution says of a policy, without a grid. ``--paired``
without a model plays the shipped climb alone.

    python experiments/learned_caution.py --export runs/caution_rl/seed_0/model.zip --into POLICY_DIR

writes a seed's policy into a policy directory (``caution_policy.npz``, NumPy, and the manifest's ``caution_policy``
and ``caution_training``), where the agent itself reads it (``LearnedInterrogator.caution_policy``; ``cof-gym
evaluate --agents interrogator:POLICY_DIR``).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from functools import lru_cache
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from script_checks import check_out_dir, check_out_file  # noqa: E402

import cof_gym  # noqa: E402
from cof_gym.agents.base import agent_view  # noqa: E402
from cof_gym.agents.policy_files import MANIFEST_FILE, MODEL_NAMES, TRAINING_RECORD  # noqa: E402
from cof_gym.agents.interrogator import (  # noqa: E402
    CAUTION_POLICY_FILE, CAUTION_SPAN, CLIMB_STATE_FIELDS, SHIPPED_INTERROGATOR, CautionPolicy, interrogator_for,
)
from cof_gym.agents.interrogator.training import STEEP_FALL, procedural_shape  # noqa: E402
from cof_gym.commands.args import DistinctValues, Parser, float_in_range, positive_int, train_seed_int  # noqa: E402
from cof_gym.task.scenarios import MOTOR_LAG_MAX_S, NOISE_LEVEL_MAX  # noqa: E402
from cof_gym.task.sensors import SYSTEMATIC_ERRORS  # noqa: E402

TRAINING_SEED = 9_000_000  # seed k's episodes from TRAINING_SEED + 1 000 000 k: far from every grid's seeds
SHAPES = ("env", "procedural", "steep")  # a third each
NOISY_SHARE = 0.25  # episodes with the noise and the lag past the v2 draws
STATE_SIZE = len(CLIMB_STATE_FIELDS)  # what LearnedInterrogator.climb_state gives
MULTIPLIER_STEP = 10.0  # PPO-Lagrangian's dual step: return per runaway, per unit of runaway rate over the budget
PAIRED_SEED = 8_500_000  # --paired's episodes: outer seeds of their own, apart from every training run's


def steered(agent, policy):
    """The interrogator ``agent`` with the caution policy ``policy`` (``policy(state) -> a``, e.g. :func:`ppo_policy`)
    setting each decision's caution, as a policy directory's would (``LearnedInterrogator.caution_policy``)."""
    agent.caution_policy = policy
    return agent


def ensemble_members(model_path: Path) -> list[Path]:
    """The model files a ``--caution-policy`` argument names: one, or several joined by ``+`` (an ensemble)."""
    return [Path(part) for part in str(model_path).split("+")]


@lru_cache(maxsize=None)
def load_ppo(path: Path):
    """A saved PPO model on the CPU (stable-baselines3), loaded once per path and process: the check before any play
    and the play itself read the same object."""
    from stable_baselines3 import PPO

    return PPO.load(str(path), device="cpu")


def check_caution_model(parser: Parser, option: str, path: Path) -> None:
    """A usage error naming ``option`` unless ``path`` is a PPO model this script trains (its observation the climb's
    state, its action one caution): loaded here, before any episode is played or anything written."""
    if not path.is_file():
        parser.error(f"{option}: no file {path} (a seed's model.zip of experiments/learned_caution.py)")
    try:
        model = load_ppo(Path(path))
    except Exception as e:  # noqa: BLE001 - SB3 and zipfile report a bad file in many exception types
        parser.error(f"{option}: {path} is not a PPO model ({type(e).__name__}: {' '.join(str(e).split())[:120]})")
    shapes = (model.observation_space.shape, model.action_space.shape)
    if shapes != ((STATE_SIZE,), (1,)):
        parser.error(f"{option}: {path} is a PPO model of another task (observation and action shapes {shapes}; a "
                     f"caution policy reads {STATE_SIZE} numbers and sets 1)")


def ppo_policy(model_path: Path):
    """The deterministic action of a saved PPO model, as :func:`steered` calls it (stable-baselines3's inference);
    for several models joined by ``+``, the mean of their actions (an ensemble of seeds, rule 107)."""
    models = [load_ppo(path) for path in ensemble_members(model_path)]
    return lambda state: float(np.mean([m.predict(state, deterministic=True)[0][0] for m in models]))


def exported(model_path: Path) -> CautionPolicy:
    """A saved PPO model's deterministic policy as the package runs it (NumPy, float32): its policy network's tanh
    layers and its action layer."""
    policy = load_ppo(Path(model_path)).policy
    layers = [m for m in policy.mlp_extractor.policy_net if hasattr(m, "weight")]
    pair = lambda m: (m.weight.detach().numpy().copy(), m.bias.detach().numpy().copy())  # noqa: E731
    return CautionPolicy(tuple(pair(m) for m in layers), pair(policy.action_net))


class CautionEnv(gym.Env):
    """The task with the shipped interrogator driving it and the policy setting its caution (module docstring)."""

    observation_space = gym.spaces.Box(-np.inf, np.inf, (STATE_SIZE,), np.float32)
    action_space = gym.spaces.Box(-1.0, 1.0, (1,), np.float32)

    def __init__(self, counter_torque: bool = False, interrogator: Path = SHIPPED_INTERROGATOR) -> None:
        self.env = gym.make(cof_gym.WAGON_ENV_ID, counter_torque=counter_torque)
        self.agent = interrogator_for(self.env, interrogator)
        self._obs, self._info = None, None

    def _options(self) -> dict:
        """The episode's reset options (module docstring), from this env's ``np_random``."""
        rng = self.np_random
        shape = SHAPES[int(rng.integers(len(SHAPES)))]
        options: dict[str, Any] = {}
        if shape != "env":
            options["creep_law"] = procedural_shape(rng, STEEP_FALL) if shape == "steep" else procedural_shape(rng)
        gain = SYSTEMATIC_ERRORS["torque_gain_error"].accepted
        options["torque_gain_error"] = float(rng.uniform(-gain, gain))
        if rng.random() < NOISY_SHARE:
            options["noise_level"] = float(rng.uniform(0.0, NOISE_LEVEL_MAX))
            options["motor_lag_s"] = float(rng.uniform(0.0, MOTOR_LAG_MAX_S))
        return options

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        inner_seed = int(self.np_random.integers(2**31))
        obs, info = self.env.reset(seed=inner_seed, options=self._options())
        self.agent.caution_policy = None
        self.agent.reset(obs, agent_view(info, False))
        first = self.agent.act(obs, agent_view(info, False))  # the first window: the climb's fixed first DC
        self._obs, _, terminated, truncated, self._info = self.env.step(first)
        if terminated or truncated:  # cannot happen at the first DC; a reset that ends at once would hide a bug
            raise RuntimeError("the first window ended the episode")
        return self.agent.climb_state(), {}

    def step(self, action):
        a = float(np.asarray(action).reshape(-1)[0])
        self.agent.caution_policy = lambda state: a  # the climb clips it to [-1, 1]
        command = self.agent.act(self._obs, agent_view(self._info, False))
        self._obs, reward, terminated, truncated, self._info = self.env.step(command)
        cost = float(self._info["cost"]["macro_slip"])  # 1 when this window's wheel ran away
        return self.agent.climb_state(), float(reward), terminated, truncated, {"cost": cost}

    def close(self) -> None:
        self.env.close()


def lagrangian(envs, budget: float, step: float = MULTIPLIER_STEP):
    """``envs`` (a VecEnv of :class:`CautionEnv`) with PPO-Lagrangian's reward: the task's reward less a multiplier
    times the runaway cost (``info["cost"]``), and a callback that moves the multiplier after each rollout by
    dual ascent, ``max(0, multiplier + step (runaways per finished episode - budget))`` (Altman 1999, *Constrained
    Markov Decision Processes*; Ray, Achiam & Amodei 2019, *Benchmarking Safe Exploration in Deep RL*, PPO-Lagrangian).
    Returns ``(wrapped envs, callback)``; the callback's ``history`` holds each rollout's rate and multiplier."""
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecEnvWrapper

    class CostPricedEnv(VecEnvWrapper):
        multiplier, episodes, runaways = 0.0, 0, 0.0

        def reset(self):
            return self.venv.reset()

        def step_wait(self):
            obs, rewards, dones, infos = self.venv.step_wait()
            costs = np.array([info.get("cost", 0.0) for info in infos])
            self.episodes += int(dones.sum())
            self.runaways += float(costs.sum())
            return obs, rewards - self.multiplier * costs, dones, infos

    class DualAscent(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.history: list[dict] = []

        def _on_step(self) -> bool:
            return True

        def _on_rollout_end(self) -> None:
            if priced.episodes:
                rate = priced.runaways / priced.episodes
                priced.multiplier = max(0.0, priced.multiplier + step * (rate - budget))
                self.history.append({"episodes": priced.episodes, "runaway_rate": round(rate, 4),
                                     "multiplier": round(priced.multiplier, 4)})
                priced.episodes, priced.runaways = 0, 0.0

    priced = CostPricedEnv(envs)
    return priced, DualAscent()


def train(out: Path, seed: int, timesteps: int, budget: float | None = None) -> dict:
    """One seed's PPO run (both vehicle configurations, one process each), saved in ``out/seed_K``; with a runaway
    ``budget`` (per episode) PPO-Lagrangian (:func:`lagrangian`)."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.monitor import Monitor
    from stable_baselines3.common.vec_env import SubprocVecEnv

    start = time.time()
    factories = [lambda: Monitor(CautionEnv(counter_torque=False)), lambda: Monitor(CautionEnv(counter_torque=True))]
    envs = SubprocVecEnv(factories)
    envs.seed(TRAINING_SEED + 1_000_000 * seed)
    callback = None
    if budget is not None:
        envs, callback = lagrangian(envs, budget)
    model = PPO("MlpPolicy", envs, n_steps=512, batch_size=256, n_epochs=10, learning_rate=3e-4, gamma=1.0,
                gae_lambda=0.95, ent_coef=0.0, policy_kwargs={"net_arch": [64, 64], "log_std_init": -1.0},
                seed=seed, device="cpu", verbose=1)
    model.learn(total_timesteps=timesteps, callback=callback)
    directory = out / f"seed_{seed}"
    directory.mkdir(parents=True, exist_ok=True)
    model.save(directory / MODEL_NAMES[0])
    envs.close()
    record = {"seed": seed, "timesteps": timesteps, "training_seed": TRAINING_SEED + 1_000_000 * seed,
              "caution_span": CAUTION_SPAN, "shapes": SHAPES, "noisy_share": NOISY_SHARE,
              "seconds": round(time.time() - start, 1)}
    if callback is not None:
        record |= {"cost_budget": budget, "multiplier_step": MULTIPLIER_STEP, "dual_ascent": callback.history}
    (directory / TRAINING_RECORD).write_text(json.dumps(record, indent=1) + "\n")
    return record


def read_play(play: str) -> list[dict]:
    """The episodes of ``crest_tradeoff.py --records`` files joined by ``+``, in their order (ValueError for a file
    that is no such records file: :func:`paired_comparison.read_records`)."""
    from paired_comparison import read_records

    return [r for path in play.split("+") for r in read_records(Path(path), set())]


def seed_report(plays: list[str], baseline: str) -> str:
    """The seeds' plays and the baseline's (module docstring), as markdown."""
    from ppo_seeds import iqm, stratified_bootstrap_ci

    names = [f"baseline: {baseline.split('+')[0]}", *(p.split("+")[0] for p in plays)]
    played = [read_play(p) for p in [baseline, *plays]]  # the baseline first
    keys = [[(r["grid"], json.dumps(r["config"], sort_keys=True), r["episode"]) for r in s] for s in played]
    if any(k != keys[0] for k in keys[1:]):
        raise ValueError("the plays do not hold the same episodes in the same order")
    errors = np.array([[r["error"] for r in s] for s in played])
    returns = [float(np.mean([r["episode_return"] for r in s])) for s in played]
    lines = ["| play | runaways (climbs) | median | P90 | mean return | IQM |", "|---|---|---|---|---|---|"]
    lines += [f"| {name} | {sum(r['macro_slip'] for r in s)} of {len(s)} | {100 * np.median(e):.1f} % | "
              f"{100 * np.percentile(e, 90):.1f} % | {mean:.4f} | {100 * iqm(e):.1f} % |"
              for name, s, e, mean in zip(names, played, errors, returns)]
    low, high = stratified_bootstrap_ci(errors[1:], iqm)
    lines += ["", f"Over {len(plays)} seeds x {errors.shape[1]} climbs: IQM of the relative error "
              f"{100 * iqm(errors[1:]):.1f} % [{100 * low:.1f}, {100 * high:.1f}] (stratified bootstrap 95 % CI; the "
              f"baseline {100 * iqm(errors[0]):.1f} %); mean return {np.mean(returns[1:]):.4f} "
              f"(seeds {min(returns[1:]):.4f} ... {max(returns[1:]):.4f}; the baseline {returns[0]:.4f})."]
    return "\n".join(lines) + "\n"


def episode_return(env: CautionEnv, policy, seed: int) -> tuple[float, float]:
    """The return of one episode of ``env`` (reset with ``seed``) under ``policy``, the first window's reward
    excepted (the climb's fixed first DC: the same for every policy), and 1.0 if its wheel ran away (else 0.0)."""
    state, _ = env.reset(seed=seed)
    total = 0.0
    while True:
        state, reward, terminated, truncated, info = env.step(np.array([policy(state)], dtype=np.float32))
        total += reward
        if terminated or truncated:
            return total, info["cost"]


def paired_returns(model_path: Path | None, episodes: int) -> str:
    """The shipped climb's and the model's returns and runaways on the same ``episodes`` training-draw episodes per
    vehicle configuration, and their paired difference (mean +- standard error); the shipped climb's alone without
    a model."""
    policies = [lambda state: 0.0] + ([ppo_policy(model_path)] if model_path is not None else [])
    played = []  # per episode: (return, runaway) of each policy
    for counter_torque in (False, True):
        env = CautionEnv(counter_torque=counter_torque)
        seeds = range(PAIRED_SEED, PAIRED_SEED + episodes)
        played += [[episode_return(env, policy, s) for policy in policies] for s in seeds]
        env.close()
    results = np.array(played)  # episode x policy x (return, runaway)
    shipped = results[:, 0, 0]
    line = (f"{len(played)} training-draw episodes: the shipped climb's mean return {shipped.mean():.4f}, "
            f"{int(results[:, 0, 1].sum())} runaways")
    if model_path is None:
        return line + "\n"
    model, difference = results[:, 1, 0], results[:, 1, 0] - shipped
    return (f"{model_path}: {line}; the model's {model.mean():.4f}, {int(results[:, 1, 1].sum())} runaways; "
            f"difference {difference.mean():+.4f} +- {difference.std(ddof=1) / np.sqrt(len(played)):.4f} "
            f"(standard error)\n")


TRAINING_SEEDS = (0, 1, 2, 3, 4)  # the PPO seeds trained when --seeds is not given
TRAINING_TIMESTEPS = 40_000  # PPO steps per seed when --timesteps is not given
PAIRED_EPISODES = 60  # --paired's episodes per vehicle configuration when --episodes is not given
OPTION_MODES = {  # the options that only some of the script's jobs read (default None: "not given")
    "--out": ("training", "report"),
    "--seeds": ("training",),
    "--timesteps": ("training",),
    "--cost-budget": ("training",),
    "--episodes": ("paired",),
    "--baseline": ("report",),
}
MODE_WORDS = {"training": "when training", "paired": "with --paired", "report": "with --report",
              "export": "with --export/--into"}


def build_parser() -> Parser:
    parser = Parser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, default=None,
                        help="directory of the seeds' models (training), or the report's markdown file (--report)")
    parser.add_argument("--report", nargs="+", default=None, metavar="PLAY",
                        help="no training: report these seeds' plays (crest_tradeoff.py --records files of one seed "
                             "joined by +) beside --baseline's")
    parser.add_argument("--baseline", default=None, metavar="PLAY", help="the play the report sets the seeds beside")
    parser.add_argument("--export", type=Path, default=None, metavar="MODEL",
                        help="no training: write this seed's model.zip into the policy directory --into")
    parser.add_argument("--paired", type=Path, nargs="?", const=True, default=None, metavar="MODEL",
                        help="no training: this model and the shipped climb on the same training-draw episodes (the "
                             "shipped climb alone without MODEL)")
    parser.add_argument("--cost-budget", type=float_in_range(0.0, 1.0, low_inclusive=True), default=None,
                        metavar="RATE",
                        help="train by PPO-Lagrangian with at most RATE runaways per episode (in [0, 1]; default: "
                             "plain PPO on the task's return)")
    parser.add_argument("--episodes", type=positive_int, default=None,
                        help=f"--paired's episodes per vehicle configuration (default: {PAIRED_EPISODES})")
    parser.add_argument("--into", type=Path, default=None, metavar="POLICY_DIR",
                        help="a policy directory (with its manifest.json) that --export writes the policy into")
    parser.add_argument("--seeds", type=train_seed_int, nargs="+", default=None, action=DistinctValues,
                        help=f"PPO seeds (>= 0; default: {' '.join(map(str, TRAINING_SEEDS))})")
    parser.add_argument("--timesteps", type=positive_int, default=None,
                        help=f"PPO steps per seed (default: {TRAINING_TIMESTEPS})")
    return parser


def mode_of(args: argparse.Namespace) -> str:
    """Which of the script's four jobs the arguments ask for (a key of :data:`MODE_WORDS`)."""
    if args.paired is not None:
        return "paired"
    if args.export is not None or args.into is not None:
        return "export"
    return "report" if args.report is not None else "training"


def reject_unused_options(parser: Parser, args: argparse.Namespace, mode: str) -> None:
    """One line and exit code 2 for an option the job ``mode`` would not read (none is silently ignored)."""
    for option, modes in OPTION_MODES.items():
        if mode not in modes and getattr(args, option.lstrip("-").replace("-", "_")) is not None:
            parser.error(f"{option}: only {' or '.join(MODE_WORDS[m] for m in modes)}, not {MODE_WORDS[mode]}")


def main() -> None:
    parser = build_parser()
    args = parser.parse_args()
    mode = mode_of(args)
    reject_unused_options(parser, args, mode)
    seeds = TRAINING_SEEDS if args.seeds is None else args.seeds
    if mode == "paired":
        model = None if args.paired is True else args.paired  # --paired alone: the shipped climb's episodes
        if model is not None:
            check_caution_model(parser, "--paired", model)
        print(paired_returns(model, args.episodes or PAIRED_EPISODES), end="")
        return
    if mode == "export":
        export(parser, args)
        return
    if args.out is None:
        parser.error("--out: required (the seeds' directory, or with --report the report's file)")
    if mode == "report":
        report(parser, args)
        return
    check_out_dir(parser, "--out", args.out)
    for seed in seeds:
        print(json.dumps(train(args.out, seed, args.timesteps or TRAINING_TIMESTEPS, args.cost_budget)), flush=True)


def export(parser: Parser, args: argparse.Namespace) -> None:
    """``--export MODEL --into DIR``: the model's policy written into the policy directory (module docstring)."""
    if args.export is None or args.into is None:
        parser.error("--export and --into go together (a seed's model.zip, a policy directory)")
    manifest_path = args.into / MANIFEST_FILE
    if args.export.is_file() and not manifest_path.is_file():  # the cheap check first: loading a model takes seconds
        parser.error(f"--into: no manifest.json in {args.into} (a policy directory)")
    check_caution_model(parser, "--export", args.export)
    training = args.export.parent / TRAINING_RECORD
    exported(args.export).save(args.into / CAUTION_POLICY_FILE)
    manifest = json.loads(manifest_path.read_text())
    manifest["caution_policy"] = CAUTION_POLICY_FILE
    manifest["caution_training"] = json.loads(training.read_text()) if training.is_file() else {}
    manifest_path.write_text(json.dumps(manifest, indent=2) + "\n")
    print(f"{args.export} -> {args.into / CAUTION_POLICY_FILE}")


def report(parser: Parser, args: argparse.Namespace) -> None:
    """``--report``: the seeds' plays beside the baseline's, printed and written to ``--out``."""
    check_out_file(parser, "--out", args.out)
    if args.baseline is None:
        parser.error("--report: needs --baseline (the play the seeds are set beside)")
    for play in [*args.report, args.baseline]:
        missing = [p for p in play.split("+") if not Path(p).is_file()]
        if missing:
            parser.error(f"--report/--baseline: no records file {missing[0]}")
    try:
        text = seed_report(args.report, args.baseline)
    except (ValueError, KeyError, json.JSONDecodeError) as error:
        parser.error(f"--report: {error}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(text, end="")


if __name__ == "__main__":
    main()

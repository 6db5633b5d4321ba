"""Play a model trained by RL Zoo on a registered id, with any algorithm cof_gym plays (run from the repository root):

    python experiments/zoo_eval.py out/zoo/ppo/CofGym-TorqueInterrogation-v1_1/CofGym-TorqueInterrogation-v1.zip

RL Zoo writes no ``train_meta.json``; the env id and the env's interface come from the run's ``args.yml`` and
``config.yml`` (:func:`~cof_gym.agents.sb3_policy.zoo_training`: the ``env_kwargs`` the model was trained with), or, for
a zip without them, from ppo.yml's ``env_kwargs`` for the v2 wagon. The policy acts deterministically, through the
agent-side interface, on a default env for ``--episodes`` draws of the env's distribution (seeds 10000 + i, not the
suites'), and the mean episode length, the median / P90 relative error and the macro-slips are printed.
``cof-gym evaluate --agents sb3:PATH`` plays the same model on the suites beside every other agent.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import cof_gym
from cof_gym.commands.args import Parser, positive_int
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.agents.sb3_policy import SB3Agent, check_model, resolve_model_path, zoo_training
from cof_gym.commands.train_hyperparams import load_hyperparams

FIRST_SEED = 10_000


def main() -> None:
    parser = Parser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("model", help="the RL Zoo model zip")
    parser.add_argument("--episodes", type=positive_int, default=40)
    args = parser.parse_args()
    try:  # a missing file, one that is no model, unusable statistics or metadata: one line naming the argument
        path = resolve_model_path(args.model)
        check_model(path)
        if zoo_training(path) is None:  # a bare zip: ppo.yml's interface for the v2 wagon
            env_kwargs = {k: v for k, v in load_hyperparams(cof_gym.WAGON_ENV_ID).get("env_kwargs", {}).items()
                          if k != "shaping"}
            agent = SB3Agent.load(path, env_id=cof_gym.WAGON_ENV_ID, env_kwargs=env_kwargs)
        else:
            agent = SB3Agent.load(path)
    except (FileNotFoundError, ValueError) as error:
        parser.error(f"model: {' '.join(str(error).split())}")
    env = gym.make(agent.env_id)
    records = [run_episode(env, agent, FIRST_SEED + i, {}, i) for i in range(args.episodes)]
    lengths = [r.steps for r in records]
    errors = [r.relative_error for r in records]
    slips = sum(r.macro_slip for r in records)
    print(f"{args.episodes} episodes: mean length {np.mean(lengths):.1f} windows, median rel. error "
          f"{np.median(errors):.1%}, P90 {np.percentile(errors, 90):.1%}, macro-slips {slips}")


if __name__ == "__main__":
    main()

"""Where policies live: the shipped policies' directories and the files a policy directory holds (one definition,
read by the registry, the agents that load them, training and the experiment scripts)."""

from __future__ import annotations

from pathlib import Path

from cof_gym import WAGON_ENV_ID, WAGON_IN_SERVICE_ENV_ID

POLICIES_DIR = Path(__file__).resolve().parent / "policies"
SHIPPED_PPO = POLICIES_DIR / "ppo_wagon"  # the v1 PPO policy (the ``ppo`` agent)
SHIPPED_INTERROGATOR = POLICIES_DIR / "interrogator"  # the learned interrogator's networks (``interrogator``)
# the same recipe's networks fitted on task v3's wagon (``interrogator-in-service``; rule 144, session 88)
SHIPPED_INTERROGATOR_IN_SERVICE = POLICIES_DIR / "interrogator_in_service"
# the learned interrogator's package of each env id its recipe runs on (experiments/train_interrogator.py --env, --ship)
SHIPPED_INTERROGATORS = {WAGON_ENV_ID: SHIPPED_INTERROGATOR, WAGON_IN_SERVICE_ENV_ID: SHIPPED_INTERROGATOR_IN_SERVICE}

# a Stable-Baselines3 policy (cof-gym train's output, an RL Zoo run)
MODEL_NAMES = ("model.zip", "best_model.zip")  # looked for, in this order, when given a directory
VECNORMALIZE_NAME = "vecnormalize.pkl"  # its observation statistics, beside the model
META_NAME = "train_meta.json"  # how cof-gym train made it
# a learned interrogator's policy directory
MANIFEST_FILE = "manifest.json"  # its climb, training distribution and named networks
TRAINING_RECORD = "training.json"  # what a directory's networks were fitted on

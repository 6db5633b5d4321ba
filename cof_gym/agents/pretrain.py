"""Behaviour-cloning warm start: fit a fresh PPO policy to the practical staircase before RL.

From scratch, PPO on this task collapses to "stop at once with a guess" (episode length ~1.1, median
error ~50 %): finding a torque ramp that pays off only at the end is a hard exploration problem. Cloning
the staircase's (observation, action) pairs gives PPO a policy that already interrogates; RL then
improves the estimate and the trade-offs. The observation-normalisation statistics are seeded from the
demonstrations so that the cloned policy sees the inputs it will see during training.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import torch

from cof_gym.agents.staircase import PracticalStaircase, limits_of
from cof_gym.task.interface import ACTION_NAMES

STOP = ACTION_NAMES.index("stop")


def collect_demonstrations(env_id: str, env_kwargs: dict, episodes: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(observations, actions) of the practical staircase over ``episodes`` seeded episodes."""
    env = gym.make(f"cof_gym:{env_id}", **{k: v for k, v in env_kwargs.items() if k != "max_episode_steps"})
    agent = PracticalStaircase(limits_of(env))
    obs_list, act_list = [], []
    for i in range(episodes):
        obs, info = env.reset(seed=seed + i)
        agent.reset(obs, info)
        while True:
            action = agent.act(obs, info)
            obs_list.append(obs)
            act_list.append(action)
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                break
    env.close()
    return np.asarray(obs_list, dtype=np.float32), np.asarray(act_list, dtype=np.float32)


def behaviour_clone(model, observations: np.ndarray, actions: np.ndarray, epochs: int = 40, batch_size: int = 256,
                    learning_rate: float = 1e-3, log_std: float = -1.0, seed: int = 0) -> float:
    """Fit the policy's mean action to the demonstrations (MSE) and set its exploration noise; seeds the
    VecNormalize observation statistics. Returns the final training MSE."""
    vec_normalize = model.get_vec_normalize_env()
    if vec_normalize is not None:
        vec_normalize.obs_rms.update(observations)
        inputs = vec_normalize.normalize_obs(observations)
    else:
        inputs = observations
    policy = model.policy
    x = torch.as_tensor(inputs, dtype=torch.float32, device=policy.device)
    y = torch.as_tensor(np.clip(actions, -1.0, 1.0), dtype=torch.float32, device=policy.device)
    params = [p for name, p in policy.named_parameters() if not name.startswith(("value_net", "mlp_extractor.value"))]
    optimizer = torch.optim.Adam(params, lr=learning_rate)
    # the stop request is one sample per episode: weight it as much as the rest of the episode
    weights = torch.ones_like(y)
    stops = y[:, STOP] > 0
    weights[stops, STOP] = max(1.0, float((~stops).sum()) / max(int(stops.sum()), 1))
    generator = torch.Generator().manual_seed(seed)
    loss_value = float("nan")
    for _ in range(epochs):
        order = torch.randperm(len(x), generator=generator)
        for start in range(0, len(x), batch_size):
            idx = order[start:start + batch_size]
            mean = policy.get_distribution(x[idx]).distribution.mean
            loss = torch.mean(weights[idx] * (mean - y[idx]) ** 2)
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            loss_value = float(loss.detach())
    with torch.no_grad():
        policy.log_std.fill_(log_std)
    return loss_value

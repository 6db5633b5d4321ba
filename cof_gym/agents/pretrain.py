"""Behaviour-cloning warm start: fit a fresh PPO policy (and its value function) to a scripted expert
before RL.

From scratch, PPO on this task needs a long time to find a torque climb that pays off only at the end
(and with the absolute interface collapses to "stop at once with a guess"). Cloning an expert's
(observation, action) pairs gives PPO a policy that already interrogates; RL then improves the
trade-offs the reward states (accuracy, time, comfort, slip). The expert acts in the training env's
own action type: its command is re-encoded through ``task.actions.encode`` with the episode's context,
so the demonstrations are actions the policy can take. The executed actions are perturbed with
Gaussian noise (``noise_std`` on the torque, amplitude, frequency and estimate components; the
labels stay the expert's clean actions: DART, Laskey et al. 2017, "DART: Noise Injection for Robust
Imitation Learning"), so that the clone also knows what to do in the states its own exploration
reaches: cloned from clean demonstrations only, the policy stopped after ~5 windows with errors of
50-90 % as soon as PPO's exploration noise moved it off the expert's path. The value function is fitted to the
demonstrations' discounted returns, so that the first PPO updates start from sensible advantages; the
observation-normalisation statistics are seeded from the demonstrations.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from cof_gym.agents.base import agent_view
from cof_gym.agents.registry import make_agent
from cof_gym.agents.staircase import limits_of
from cof_gym.envs.torque_interrogation import make_kwargs
from cof_gym.task.interface import ACTION_NAMES, OBSERVATION_NAMES, decode_action

STOP = ACTION_NAMES.index("stop")
EXPERTS = ("model-based", "staircase")  # registry names of the scripted agents that know no ground truth


def collect_demonstrations(env_id: str, env_kwargs: dict, episodes: int, seed: int, expert: str = "model-based",
                           gamma: float = 0.95, noise_std: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(observations, actions, discounted returns-to-go) of ``expert`` over ``episodes`` seeded episodes,
    the actions in the env's action type. The expert reads the window part of the observation; the env
    executes its action plus N(0, ``noise_std``) on every component but the stop (the label is the
    clean action)."""
    env = gym.make(f"cof_gym:{env_id}", **make_kwargs(env_kwargs))
    base = env.unwrapped
    limits = limits_of(env)
    agent = make_agent(f"{expert}+plain", env)  # no runaway estimate: the shipped PPO recipe's demonstrations
    window = len(OBSERVATION_NAMES)
    obs_list, act_list, ret_list = [], [], []
    rng = np.random.default_rng(seed)
    perturbed = np.arange(len(ACTION_NAMES)) != STOP
    for i in range(episodes):
        obs, info = env.reset(seed=seed + i)
        agent.reset(obs[:window], agent_view(info, oracle=False))
        rewards = []
        while True:
            d = decode_action(agent.act(obs[:window], agent_view(info, oracle=False)).astype(np.float64), limits)
            action = base.task.actions.encode(base.episode.action_context, d.drive.dc_torque_nm, d.drive.amplitude_nm,
                                              d.drive.frequency_hz, d.cof_estimate, d.stop, limits)
            obs_list.append(obs)
            act_list.append(action)
            executed = np.clip(action + perturbed * rng.normal(0.0, noise_std, len(action)), -1.0, 1.0)
            obs, reward, terminated, truncated, info = env.step(executed.astype(np.float32))
            rewards.append(reward)
            if terminated or truncated:
                break
        ret_list.extend(discounted_returns(np.asarray(rewards), gamma))
    env.close()
    return (np.asarray(obs_list, dtype=np.float32), np.asarray(act_list, dtype=np.float32),
            np.asarray(ret_list, dtype=np.float32))


def discounted_returns(rewards: np.ndarray, gamma: float) -> np.ndarray:
    """Return-to-go ``G_t = r_t + gamma G_{t+1}`` of one episode."""
    out = np.zeros(len(rewards))
    running = 0.0
    for t in range(len(rewards) - 1, -1, -1):
        running = rewards[t] + gamma * running
        out[t] = running
    return out


def behaviour_clone(model, observations: np.ndarray, actions: np.ndarray, returns: np.ndarray | None = None,
                    epochs: int = 100, batch_size: int = 256, learning_rate: float = 1e-3, log_std: float | list[float] | None = None,
                    seed: int = 0) -> dict[str, float]:
    """Fit the policy's mean action to the demonstrations (MSE, the one stop sample per episode weighted
    as much as the rest of the episode) and, when ``returns`` are given, the value function to them;
    set the exploration noise to ``log_std`` (one value, one per action component, or None: keep the
    policy's ``log_std_init``); seed the
    VecNormalize observation statistics. Returns the final training losses."""
    import torch  # here: building the CLI parser (the EXPERTS choices) imports no torch

    vec_normalize = model.get_vec_normalize_env()
    if vec_normalize is not None:
        vec_normalize.obs_rms.update(observations)
        inputs = vec_normalize.normalize_obs(observations)
    else:
        inputs = observations
    policy = model.policy
    x = torch.as_tensor(inputs, dtype=torch.float32, device=policy.device)
    y = torch.as_tensor(np.clip(actions, -1.0, 1.0), dtype=torch.float32, device=policy.device)
    g = None if returns is None else torch.as_tensor(returns, dtype=torch.float32, device=policy.device)
    params = [p for name, p in policy.named_parameters() if name != "log_std"]
    optimizer = torch.optim.Adam(params, lr=learning_rate)
    weights = torch.ones_like(y)
    stops = y[:, STOP] > 0
    weights[stops, STOP] = max(1.0, float((~stops).sum()) / max(int(stops.sum()), 1))
    generator = torch.Generator().manual_seed(seed)
    losses = {"action_mse": float("nan"), "value_mse": float("nan")}
    for _ in range(epochs):
        order = torch.randperm(len(x), generator=generator)
        for start in range(0, len(x), batch_size):
            idx = order[start:start + batch_size]
            mean = policy.get_distribution(x[idx]).distribution.mean
            action_loss = torch.mean(weights[idx] * (mean - y[idx]) ** 2)
            loss = action_loss
            if g is not None:
                value_loss = torch.mean((policy.predict_values(x[idx]).squeeze(-1) - g[idx]) ** 2)
                loss = loss + value_loss / max(float(g.var()), 1e-6)  # both terms O(1)
                losses["value_mse"] = float(value_loss.detach())
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            losses["action_mse"] = float(action_loss.detach())
    if log_std is not None:
        with torch.no_grad():
            policy.log_std.copy_(torch.as_tensor(np.broadcast_to(log_std, policy.log_std.shape).copy()))
    return losses

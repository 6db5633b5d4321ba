"""How each agent's CoF error moves with one systematic sensor error at the end of the range the env accepts
(information only: nothing is chosen here). (Run from the repository root; 2 cores, about 17 min.)

    python experiments/sensor_sensitivity.py [--agents oracle,staircase,phase-rule,...,interrogator]
                                             [--workers 2] [--out out/sensor_sensitivity.md]

Plays every agent on the family validation grid (the v2 draws' creep laws, both vehicle configurations:
model-selection data, never reported) as it is, and again with each systematic sensor error of
:data:`cof_gym.task.sensors.SYSTEMATIC_ERRORS` fixed over every episode at plus and minus the largest value the env
accepts (the other errors as each episode draws them: ``reset`` options over the grid's own). The v2 draws reach
only a fraction of those values, so the rows past the first measure the agents on sensors none was tuned on:

- a wheel-radius error shifts the measured creepage by a constant (the creepage offset); an agent that reads the
  creepage's changes within the climb, not its level, does not see it;
- a speed-sensor error shifts the creepage the other way and scales the measured speed;
- a force gain error scales the measured tangential force, so the measured adhesion (CoA) and every estimate read
  from it, the oracle's too (it knows where the peak is, not what the force sensor misreads): a floor no
  method that reads the force sensor alone can pass;
- a torque gain error scales the torque reading (the lock-in's compliance, a torque-based estimate);
- a lag of the encoder's speed signal (``encoder_lag_s``, a first-order time constant: the filter a wheel-speed
  estimate goes through; v1 and v2 draw none) adds ``atan(w tau)`` to every phase lag the lock-in reads and shrinks
  the compliance by ``cos`` of it: the systematic error a phase method meets first. Rows at 5 and 10 ms (about 9 and
  17 deg at 5 Hz) and at the largest lag the env accepts. The smoothing also correlates the speed fit's residual,
  so the lock-in's white-noise SE of the lag understates its scatter; ``phase-rule-ar1`` and ``robust-model-ar1``
  are the two validation-chosen agents that test the lag's significance reading the SE for a first-order
  autoregressive residual instead (``phase_lag_se_corrected_deg``), every parameter as chosen; ``phase-rule-gated``
  and ``robust-model-gated`` (not in the default list) read it only where their reset window's noise colour shows a
  smoothed speed signal;
- a pulse encoder (``encoder_pulses_per_rev`` 100, :mod:`cof_gym.physics.encoder`) reads the speed about one
  interval between pulses late (a lag offset that shrinks as the speed grows), a runout of its target wheel
  (``encoder_runout`` 0.0005) adds a ripple at the wheelset's rotation frequency, and the env argument
  ``lock_in="rotation"`` takes that ripple out of the lock-in (the last row).

Cells: median / P90 relative CoF error [%] / macro-slips, over the grid's scored episodes.
"""

from __future__ import annotations

import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import gymnasium as gym
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from script_checks import check_out_file, checked_agents, write_report  # noqa: E402
from train_interrogator import CONFIGS, VALIDATION  # noqa: E402

import cof_gym  # noqa: E402,F401  (registers the envs)
from cof_gym.agents import registry  # noqa: E402
from cof_gym.agents.base import own_env_options  # noqa: E402
from cof_gym.commands.args import Parser, positive_int  # noqa: E402
from cof_gym.commands.evaluate_episodes import run_episode  # noqa: E402
from cof_gym.commands.suites import make_suite  # noqa: E402
from cof_gym.task.scenarios import ENCODER_LAG_MAX_S  # noqa: E402
from cof_gym.task.sensors import SYSTEMATIC_ERRORS  # noqa: E402

AGENTS = ("oracle", "staircase", "phase-rule", "phase-rule-ar1", "model-based", "robust-model", "robust-model-ar1",
          "interrogator")


ENCODER_LAGS_S = (0.005, 0.01, ENCODER_LAG_MAX_S)  # the encoder's speed-signal lags played, s
# the encoder read from a speed probe's pulses (session 83): 100 per wheelset revolution, then with a target wheel's
# runout of 0.05 %, then that read by the rotation lock-in (an env argument, the rest reset options)
PULSE_ENCODERS = ({"encoder_pulses_per_rev": 100}, {"encoder_pulses_per_rev": 100, "encoder_runout": 0.0005},
                  {"encoder_pulses_per_rev": 100, "encoder_runout": 0.0005, "lock_in": "rotation"})
ENV_SETTINGS = ("lock_in",)  # settings that are the env's arguments, not a reset's options


def settings() -> list[dict[str, float | str]]:
    """The grid as drawn ({}), then each systematic error at plus and minus its accepted bound, then each encoder
    lag of ENCODER_LAGS_S, then each pulse encoder of PULSE_ENCODERS."""
    return ([{}] + [{name: sign * span.accepted} for name, span in SYSTEMATIC_ERRORS.items() for sign in (1.0, -1.0)]
            + [{"encoder_lag_s": lag} for lag in ENCODER_LAGS_S] + [dict(encoder) for encoder in PULSE_ENCODERS])


def play(spec: str, setting: dict[str, float | str], config: dict) -> list[tuple[float, bool]]:
    """(relative error, macro-slip) of every scored episode of the family validation grid, played by ``spec`` in
    the vehicle configuration ``config`` with ``setting`` over each episode's own options (its ENV_SETTINGS as the
    env's arguments)."""
    suite = make_suite(str(VALIDATION), 60, 0)
    env_setting = {k: v for k, v in setting.items() if k in ENV_SETTINGS}
    setting = {k: v for k, v in setting.items() if k not in ENV_SETTINGS}
    env = gym.make(suite.env_id, **{**suite.env_kwargs, **config, **env_setting})
    agent = registry.make_agent(spec, env)
    options = own_env_options(agent)
    if options:  # an excitation of its own (two tones): the same agent plays in an env made with it
        env.close()
        env = gym.make(suite.env_id, **{**suite.env_kwargs, **config, **env_setting, **options})
    records = [run_episode(env, agent, seed, {**own, **setting}, i) for i, (seed, own) in enumerate(suite.episodes)]
    env.close()
    return [(r.relative_error, r.macro_slip) for r in records if r.scored]


def cell(played: list[tuple[float, bool]]) -> str:
    errors = np.array([e for e, _ in played])
    return (f"{100 * np.median(errors):.1f} / {100 * np.percentile(errors, 90):.1f} / "
            f"{sum(slip for _, slip in played)}")


def label(setting: dict[str, float | str]) -> str:
    if "encoder_lag_s" in setting:
        return f"encoder_lag_s {setting['encoder_lag_s']:g} s"
    if "encoder_pulses_per_rev" in setting:  # a pulse encoder: its fields and the lock-in as given
        return ", ".join(f"{name} {value:g}" if name != "lock_in" else f"lock_in {value}" for name, value in
                         setting.items())
    return "as drawn" if not setting else ", ".join(f"{name} {value:+g}" for name, value in setting.items())


def main() -> None:
    parser = Parser(description=__doc__.split("\n")[0])
    parser.add_argument("--agents", default=",".join(AGENTS), help="comma-separated agents (cof-gym evaluate's names)")
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--out", type=Path, default=Path("out/sensor_sensitivity.md"))
    args = parser.parse_args()
    check_out_file(parser, "--out", args.out)
    agents = checked_agents(parser, "--agents", args.agents.split(","))
    rows = settings()
    jobs = [(spec, setting, config) for setting in rows for spec in agents for config in CONFIGS]
    with ProcessPoolExecutor(args.workers) as pool:
        played = list(pool.map(play, *zip(*jobs)))
    per_cell = len(CONFIGS)
    lines = ["Family validation grid, both vehicle configurations (`python experiments/sensor_sensitivity.py`): "
             "median / P90 relative CoF error [%] / macro-slips, with one systematic sensor error fixed at the end "
             "of the range the env accepts (the v2 draws: "
             + ", ".join(f"{name} +-{span.drawn:g}" for name, span in SYSTEMATIC_ERRORS.items())
             + "), or the encoder's speed signal lagged (a first-order lag the draws never give), or the encoder "
             "read from 100 pulses per revolution, with a runout of its target wheel, and that through the rotation "
             "lock-in (none of which the draws give).", "",
             "| sensors | " + " | ".join(agents) + " |", "|---" * (len(agents) + 1) + "|"]
    for r, setting in enumerate(rows):
        cells = []
        for a in range(len(agents)):
            k = (r * len(agents) + a) * per_cell
            cells.append(cell([p for part in played[k:k + per_cell] for p in part]))
        lines.append(f"| {label(setting)} | " + " | ".join(cells) + " |")
    write_report(args.out, lines)


if __name__ == "__main__":
    main()

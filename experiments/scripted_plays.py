"""The hand-built agents on crest_tradeoff.py's grids, as records: where they lie beside the learned candidates.

    python experiments/scripted_plays.py --agents phase-rule robust-model --grids validation \
        --records out/records_{agent}_validation.json
    python experiments/scripted_plays.py --agents phase-rule robust-model --grids validation --scenario noise_level=3 \
        --records out/records_{agent}_noise_level.json

Plays each agent of ``--agents`` (names of the agent registry, `cof-gym evaluate --help`; no oracle: the truth is
what the comparison is about) as `cof-gym evaluate` plays it, on the three grids of a ``crest_tradeoff.py --grids``
set in both vehicle configurations, with ``--scenario`` reset options over every episode's own, and writes one
``crest_tradeoff.py --records`` file per agent (``{agent}`` in ``--records`` is its name): the same fields and the
same episodes as the learned candidates' records, for ``experiments/frontier.py --references`` and
``paired_comparison.py``. Information only: these agents' parameters were chosen on validation seeds of their own
(``select_phase_rule.py``, ``select_robust_model.py``) and nothing is chosen here.
"""

from __future__ import annotations

import json
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from crest_tradeoff import GRID_SETS, Played  # noqa: E402
from script_checks import check_out_file, checked_agents  # noqa: E402
from train_interrogator import CONFIGS  # noqa: E402

from cof_gym.agents import registry  # noqa: E402
from cof_gym.commands.args import Parser, positive_int  # noqa: E402
from cof_gym.commands.suites import scenario_option  # noqa: E402


def play(job: tuple[str, str, Path, dict, dict]) -> list[dict]:
    """Every episode of one grid in one configuration for one agent, as crest_tradeoff.py records them."""
    import gymnasium as gym

    from cof_gym.commands.evaluate_episodes import run_episode
    from cof_gym.commands.suites import make_suite

    agent_name, grid, path, config, scenario = job
    suite = make_suite(str(path), 60, 0)
    env = gym.make(suite.env_id, **{**suite.env_kwargs, **config})
    agent = registry.make_agent(agent_name, env)
    out = []
    for i, (seed, options) in enumerate(suite.episodes):
        r = run_episode(env, agent, seed, {**options, **scenario}, i)
        out.append(Played.of(r, "macro-slip" if r.macro_slip else r.ended).as_record(agent_name, grid, config, i))
    env.close()
    return out


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("--agents", nargs="+", required=True, metavar="AGENT",
                        help="hand-built agents of the registry (no oracle), e.g. phase-rule robust-model")
    parser.add_argument("--grids", choices=sorted(GRID_SETS), default="validation",
                        help="crest_tradeoff.py's grid set (default: validation)")
    parser.add_argument("--scenario", nargs="+", default=[], metavar="NAME=VALUE", type=scenario_option,
                        help="reset options over every episode's own, as crest_tradeoff.py's (e.g. noise_level=3)")
    parser.add_argument("--records", required=True, metavar="FILE",
                        help="where each agent's records go; {agent} is replaced by its name")
    parser.add_argument("--workers", type=positive_int, default=2)
    args = parser.parse_args()
    if "{agent}" not in args.records and len(args.agents) > 1:
        parser.error("--records: name {agent} in it, one file per agent")
    args.agents = checked_agents(parser, "--agents", args.agents, "only agents that do not are compared here")
    for name in args.agents:
        check_out_file(parser, "--records", Path(args.records.replace("{agent}", name)))
    jobs = [(name, grid, path, config, dict(args.scenario)) for name in args.agents
            for grid, path in GRID_SETS[args.grids].items() for config in CONFIGS]
    with ProcessPoolExecutor(args.workers) as pool:
        played = list(pool.map(play, jobs))
    for name in args.agents:
        records = [r for job, rows in zip(jobs, played) if job[0] == name for r in rows]
        path = Path(args.records.replace("{agent}", name))
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(records, indent=1) + "\n")
        print(f"{path}: {len(records)} episodes, {sum(r['macro_slip'] for r in records)} runaways")


if __name__ == "__main__":
    main()

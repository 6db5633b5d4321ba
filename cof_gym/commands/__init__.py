"""The commands that run the agents and the physics: evaluate (and its suites and figures), train, bench,
reproduce-paper (and its README section). Above the agents; the CLI (:mod:`cof_gym.cli`) dispatches to
them. Argument helpers every command shares live in :mod:`cof_gym.commands.args`."""

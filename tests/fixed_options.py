"""An env wrapper for tests whose every reset takes given options (a training climb resets with none)."""

import gymnasium as gym


class FixedOptions(gym.Wrapper):
    """``env`` with ``options`` merged under every reset's own options."""

    def __init__(self, env, options):
        super().__init__(env)
        self._options = options

    def reset(self, *, seed=None, options=None):
        return self.env.reset(seed=seed, options={**self._options, **(options or {})})

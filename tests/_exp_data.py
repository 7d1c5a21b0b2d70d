"""A tiny simulated dataset shared by the experiment tests."""

import functools

from sklearn_hardness.datasets import make_presses

# Small enough that frame selection takes about a second, large enough for
# s0 + N * s + l presses per class with the tiny settings below.
TINY = dict(
    initial_epochs=4,
    epochs_per_query=2,
    n_iterations=2,
    n_initial=2,
    n_per_query=2,
    n_test=2,
    n_mc_samples=4,
    max_reservoir=8,
    frame_size=(16, 20),
)


@functools.lru_cache(maxsize=2)
def tiny_presses(n_per_class=8):
    return make_presses("silicone5", n_per_class=n_per_class, image_size=(32, 40), random_state=0)

"""Torch's thread count, set for a block and restored after it (the tests' one way to set it)."""

import contextlib

import torch


@contextlib.contextmanager
def torch_threads(n):
    """Run the block with ``n`` torch threads, then restore the count it had."""
    before = torch.get_num_threads()
    torch.set_num_threads(n)
    try:
        yield
    finally:
        torch.set_num_threads(before)

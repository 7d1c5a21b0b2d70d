"""StackedConvLSTMNet: K nets stepped as one equal K separate nets (CPU, tiny nets)."""

import copy
import pickle

import numpy as np
import pytest
import torch

from sklearn_hardness.models._convlstm import ConvLSTMNet
from sklearn_hardness.models._mc_sampling import MCDropout
from sklearn_hardness.models._mlp import MLPHead
from sklearn_hardness.models._stacked import StackedConvLSTMNet
from sklearn_hardness.utils._torch import seeded_torch_rng

K = 3
SEEDS = [11, 22, 33]
NET = dict(in_channels=1, n_classes=3, filters=(2, 3), input_shape=(3, 6, 8, 1))


def _separate(seeds=SEEDS, **kw):
    nets = []
    for s in seeds:
        with seeded_torch_rng(s):
            nets.append(ConvLSTMNet(**{**NET, **kw}))
    return nets


def _streams(n_steps, seed=0, batch=4):
    """K data streams: member k gets its own batches X[step, k] and labels y[step, k]."""
    g = torch.Generator().manual_seed(seed)
    X = torch.randn(n_steps, K, batch, 3, 6, 8, 1, generator=g)
    y = torch.randint(0, 3, (n_steps, K, batch), generator=g)
    return X, y


def _train_separate(nets, opts, X, y):
    losses = []
    for step in range(len(X)):
        row = []
        for k, (net, opt) in enumerate(zip(nets, opts)):
            opt.zero_grad()
            loss = torch.nn.functional.cross_entropy(net(X[step, k]), y[step, k])
            loss.backward()
            opt.step()
            row.append(loss.item())
        losses.append(row)
    return np.array(losses)


def _train_stacked(stacked, opt, X, y):
    losses = []
    for step in range(len(X)):
        opt.zero_grad()
        member = stacked.member_losses(stacked(X[step]), y[step])
        member.sum().backward()
        opt.step()
        losses.append(member.detach().numpy())
    return np.array(losses)


def test_from_seeds_builds_the_nets_separate_seeds_build():
    stacked = StackedConvLSTMNet.from_seeds(K, SEEDS, **NET)
    assert stacked.n_members == K and "n_members=3" in repr(stacked)
    for net, own in zip(stacked.unstack(), _separate()):
        assert all(isinstance(p, torch.nn.Parameter) and p.requires_grad for p in net.parameters())
        for (name, a), (name2, b) in zip(net.state_dict().items(), own.state_dict().items()):
            assert name == name2
            torch.testing.assert_close(a, b, rtol=0, atol=0)
    # the members differ from each other (their own seeds), and a random_state draws K seeds
    w = stacked.layers__0__input_conv__weight
    assert w.shape[0] == K and not torch.equal(w[0], w[1])
    again = StackedConvLSTMNet.from_seeds(K, 5, **NET)
    torch.testing.assert_close(again.head__weight, StackedConvLSTMNet.from_seeds(K, 5, **NET).head__weight)


def test_adam_training_on_k_streams_equals_k_separate_nets():
    X, y = _streams(5)
    nets = _separate(dropout=0.0)
    stacked = StackedConvLSTMNet(nets)  # copies the weights: nets train on their own below
    opts = [torch.optim.Adam(n.parameters(), lr=0.01) for n in nets]
    s_opt = torch.optim.Adam(stacked.parameters(), lr=0.01)  # one Adam, per-element moments
    sep = _train_separate(nets, opts, X, y)
    stk = _train_stacked(stacked, s_opt, X, y)
    np.testing.assert_allclose(stk, sep, rtol=1e-5, atol=1e-6)
    assert np.abs(np.diff(sep, axis=0)).max() > 1e-3  # the nets did learn: the check has teeth
    # the optimiser state of member k is that of net k's own Adam
    for k, (net, opt) in enumerate(zip(nets, opts)):
        for (name, p), q in zip(net.named_parameters(), stacked._stacked()[0].values()):
            st, own = s_opt.state[q], opt.state[p]
            torch.testing.assert_close(st["exp_avg"][k], own["exp_avg"], rtol=1e-4, atol=1e-6)
            torch.testing.assert_close(st["exp_avg_sq"][k], own["exp_avg_sq"], rtol=1e-4, atol=1e-9)
    # same weights and predictions afterwards, in evaluation mode
    Xt = torch.randn(5, 3, 6, 8, 1)
    stacked.eval()
    logits = stacked(Xt, shared_input=True)
    for k, (net, trained) in enumerate(zip(nets, stacked.unstack())):
        net.eval()
        torch.testing.assert_close(logits[k], net(Xt), rtol=1e-4, atol=1e-5)
        torch.testing.assert_close(trained(Xt), net(Xt), rtol=1e-4, atol=1e-5)


def test_a_mean_of_member_losses_would_not_be_k_separate_adams():
    # the documented rule: sum the losses. A mean scales every gradient by 1/K, which
    # Adam's eps turns into different steps; the sum reproduces separate training.
    X, y = _streams(3)
    stacked = StackedConvLSTMNet(_separate(dropout=0.0))
    twin = copy.deepcopy(stacked)
    opt, opt_mean = (torch.optim.Adam(s.parameters(), lr=0.01, eps=1e-2) for s in (stacked, twin))
    for step in range(len(X)):
        for s, o, reduce in ((stacked, opt, torch.sum), (twin, opt_mean, torch.mean)):
            o.zero_grad()
            reduce(s.member_losses(s(X[step]), y[step])).backward()
            o.step()
    nets = _separate(dropout=0.0)
    _train_separate(nets, [torch.optim.Adam(n.parameters(), lr=0.01, eps=1e-2) for n in nets], X, y)
    w_sum, w_mean = stacked.head__weight.detach(), twin.head__weight.detach()
    for k, net in enumerate(nets):
        torch.testing.assert_close(w_sum[k], net.head.weight.detach(), rtol=1e-4, atol=1e-6)
    assert (w_mean - w_sum).abs().max() > 1e-4


def test_warm_start_in_two_parts_and_through_a_pickle_equals_one_run():
    X, y = _streams(6, seed=1)
    nets = _separate(dropout=0.0)
    opts = [torch.optim.Adam(n.parameters(), lr=0.01) for n in nets]
    sep = _train_separate(nets, opts, X, y)
    stacked = StackedConvLSTMNet(_separate(dropout=0.0))
    opt = torch.optim.Adam(stacked.parameters(), lr=0.01)
    first = _train_stacked(stacked, opt, X[:3], y[:3])
    # continue in a new process' copy: pickle the net and the optimiser state
    restored = pickle.loads(pickle.dumps(stacked))
    opt2 = torch.optim.Adam(restored.parameters(), lr=0.01)
    opt2.load_state_dict(pickle.loads(pickle.dumps(opt.state_dict())))
    second = _train_stacked(restored, opt2, X[3:], y[3:])
    np.testing.assert_allclose(np.vstack([first, second]), sep, rtol=1e-5, atol=1e-6)
    # and continuing the unpickled copy did not touch the original
    assert not torch.equal(restored.head__weight, stacked.head__weight)


@pytest.mark.parametrize("placement", ["head", "layers", "channels"])
def test_members_draw_independent_dropout_masks(placement):
    # K copies of one net (same seed): any difference between members is their masks
    same = StackedConvLSTMNet(_separate([7] * K, dropout=0.5, dropout_placement=placement))
    for m in same._template.modules():
        assert not isinstance(m, MCDropout) or m.generator is None
    X = torch.randn(4, 3, 6, 8, 1)
    same.train()
    out = same(X, shared_input=True)
    assert not torch.allclose(out[0], out[1]) and not torch.allclose(out[1], out[2])
    same.eval()
    off = same(X, shared_input=True)
    torch.testing.assert_close(off[0], off[1])  # dropout off: the members agree
    torch.testing.assert_close(off[0], same.unstack()[0](X))


class _DropoutOnly(torch.nn.Module):
    """A member whose output is its dropout mask (times 1 / keep) on an input of ones."""

    def __init__(self):
        super().__init__()
        self.scale = torch.nn.Parameter(torch.ones(1))
        self.dropout = MCDropout(0.5)

    def forward(self, X, n_replicas=1):
        return self.dropout(X * self.scale)


def test_masks_keep_rate_independence_and_seeded_generator():
    stacked = StackedConvLSTMNet([_DropoutOnly() for _ in range(K)]).train()
    ones = torch.ones(400, 3)
    stacked.generator = torch.Generator().manual_seed(0)
    a = stacked(ones, shared_input=True)
    zeros = (a == 0).float()
    assert zeros.shape == (K, 400, 3)
    assert 0.45 < zeros.mean().item() < 0.55
    assert set(a.unique().tolist()) == {0.0, 2.0}  # inverted dropout: kept values scaled by 2
    # the members' masks are independent: both zero on about a quarter of the positions
    for i, j in ((0, 1), (1, 2), (0, 2)):
        assert 0.2 < (zeros[i] * zeros[j]).mean().item() < 0.3
    stacked.generator = torch.Generator().manual_seed(0)
    torch.testing.assert_close(stacked(ones, shared_input=True), a)  # the same seed, the same masks
    stacked.generator = torch.Generator().manual_seed(1)
    assert not torch.equal(stacked(ones, shared_input=True), a)
    # a member's own MCDropout generator would give every member the same mask under vmap:
    # the stacked net does not use it
    member = _DropoutOnly()
    member.dropout.generator = torch.Generator().manual_seed(3)
    out = StackedConvLSTMNet([member] * K).train()(ones, shared_input=True)
    assert not torch.equal(out[0], out[1])
    # a pickle does not carry the generator (as MCDropout)
    assert pickle.loads(pickle.dumps(stacked)).generator is None


def test_mc_replicas_and_other_member_classes():
    stacked = StackedConvLSTMNet(_separate(dropout=0.3)).eval()
    for m in stacked._template.modules():
        if isinstance(m, MCDropout):
            m.train()
    X = torch.randn(2, 3, 6, 8, 1)
    assert stacked(X, n_replicas=5, shared_input=True).shape == (K, 10, 3)
    heads = []
    for s in SEEDS:
        with seeded_torch_rng(s):
            heads.append(MLPHead(4, 3, hidden_units=5, dropout=0.0))
    stacked = StackedConvLSTMNet(heads)
    Xh = torch.randn(K, 6, 4)
    out = stacked(Xh)
    for k, h in enumerate(heads):
        torch.testing.assert_close(out[k], h(Xh[k]))


def test_member_losses_match_torch_cross_entropy():
    g = torch.Generator().manual_seed(0)
    logits, y = torch.randn(K, 6, 3, generator=g), torch.randint(0, 3, (K, 6), generator=g)
    w = torch.tensor([1.0, 2.0, 0.5])
    for weight in (None, w):
        got = StackedConvLSTMNet.member_losses(logits, y, weight)
        want = torch.stack([torch.nn.functional.cross_entropy(logits[k], y[k], weight=weight) for k in range(K)])
        torch.testing.assert_close(got, want)
    shared = StackedConvLSTMNet.member_losses(logits, y[0])
    torch.testing.assert_close(shared[2], torch.nn.functional.cross_entropy(logits[2], y[0]))


def test_device_and_dtype_moves_keep_the_members():
    stacked = StackedConvLSTMNet(_separate(dropout=0.0))
    X = torch.randn(K, 2, 3, 6, 8, 1)
    ref = stacked(X).detach()
    assert stacked.to("cpu") is stacked
    wide = copy.deepcopy(stacked).to(torch.float64)
    assert wide.head__weight.dtype == torch.float64 and wide._template.head.weight.device.type == "meta"
    torch.testing.assert_close(wide(X.double()).float(), ref, rtol=1e-4, atol=1e-5)
    assert all(p.dtype == torch.float64 for p in wide.unstack()[1].parameters())
    if torch.cuda.is_available():  # the GPU path, where there is one
        gpu = copy.deepcopy(stacked).to("cuda")
        torch.testing.assert_close(gpu(X.cuda()).cpu(), ref, rtol=1e-3, atol=1e-4)
        assert next(gpu.unstack()[0].parameters()).device.type == "cuda"


def test_bad_members_and_inputs_raise():
    with pytest.raises(ValueError, match="non-empty"):
        StackedConvLSTMNet([])
    with pytest.raises(ValueError, match="names or shapes"):
        StackedConvLSTMNet([ConvLSTMNet(1, 2, filters=(2,)), ConvLSTMNet(1, 2, filters=(3,))])
    with pytest.raises(ValueError, match="every member must be"):
        StackedConvLSTMNet([ConvLSTMNet(1, 2, filters=(2,)), MLPHead(2, 2)])
    with pytest.raises(ValueError, match="2 seeds for 3 members"):
        StackedConvLSTMNet.from_seeds(3, [1, 2], **NET)
    with pytest.raises(ValueError, match="n_members"):
        StackedConvLSTMNet.from_seeds(0, None, **NET)
    stacked = StackedConvLSTMNet.from_seeds(K, SEEDS, **NET)
    with pytest.raises(ValueError, match="shared_input=True"):
        stacked(torch.randn(2, 2, 3, 6, 8, 1))

#!/usr/bin/python3
"""Side-by-side speed of dc_learning and PyTorch on the default CNN.

Builds the same architecture as dc::default_arch() in PyTorch (U-Net-like, 4 -> 2
channels on 61x61, ~40 k weights):

    e1 conv 4->16 s1 relu [61]   e2 conv 16->32 s2 relu [31]   e3 conv 32->32 s2 relu [16]
    drop dropout 0.1 -> u2 nearest x2 to 31 (y = x[i//2, j//2]) -> d2 conv cat(u2, e2) 64->32 relu
    u1 nearest x2 to 61 -> d1 conv cat(u1, e1) 48->16 relu -> out conv 16->2 (linear)

and measures, with torch.set_num_threads(1) and (2):
  * training throughput: samples/s of full SGD steps (forward, MSE, backward, SGD with
    momentum 0.9 and weight decay 1e-4) at batch 32;
  * inference latency: median ms of a batch-1 forward under torch.no_grad() in eval mode.

Our figures come from the Google Benchmark binary build/bin/micro_conv (entries
unet_small/train_step_b32 and unet_small/infer_b1), run with OMP_NUM_THREADS=1 and 2 and
--benchmark_format=json; the median of the repetitions is used. Alternatively pass our
figures by hand with --ours "threads:train_samples_per_s:infer_ms" (repeatable).

Run:  /usr/bin/python3 benchmarks/compare/torch_compare.py [--bench build-cnn/bin/micro_conv] [--reps 5]
Both sides measure wall-clock time on the same machine; on a shared machine run it several
times and compare medians.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

import torch
import torch.nn as nn
import torch.nn.functional as F

H = W = 61
C_IN, C_OUT, BATCH = 4, 2, 32


class UNetSmall(nn.Module):
    def __init__(self, cin=C_IN, cout=C_OUT, p=0.1):
        super().__init__()
        self.e1 = nn.Conv2d(cin, 16, 3, 1, 1)
        self.e2 = nn.Conv2d(16, 32, 3, 2, 1)
        self.e3 = nn.Conv2d(32, 32, 3, 2, 1)
        self.drop = nn.Dropout(p)
        self.d2 = nn.Conv2d(64, 32, 3, 1, 1)
        self.d1 = nn.Conv2d(48, 16, 3, 1, 1)
        self.out = nn.Conv2d(16, cout, 3, 1, 1)

    @staticmethod
    def up(x, h, w):
        # Nearest x2 with an explicit (possibly odd) size, identical to dc::Upsample2x.
        return x.repeat_interleave(2, dim=2)[:, :, :h].repeat_interleave(2, dim=3)[:, :, :, :w]

    def forward(self, x):
        e1 = F.relu(self.e1(x))
        e2 = F.relu(self.e2(e1))
        e3 = self.drop(F.relu(self.e3(e2)))
        d2 = F.relu(self.d2(torch.cat([self.up(e3, e2.shape[2], e2.shape[3]), e2], 1)))
        d1 = F.relu(self.d1(torch.cat([self.up(d2, e1.shape[2], e1.shape[3]), e1], 1)))
        return self.out(d1)


def torch_figures(threads, min_seconds=3.0):
    torch.set_num_threads(threads)
    torch.manual_seed(0)
    net = UNetSmall()
    assert sum(p.numel() for p in net.parameters()) == 40162
    opt = torch.optim.SGD(net.parameters(), lr=5e-3, momentum=0.9, weight_decay=1e-4)
    x = torch.randn(BATCH, C_IN, H, W)
    t = torch.randn(BATCH, C_OUT, H, W)

    def step():
        opt.zero_grad(set_to_none=True)
        loss = F.mse_loss(net(x), t)
        loss.backward()
        opt.step()

    net.train()
    for _ in range(3):
        step()
    steps, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < min_seconds:
        step()
        steps += 1
    train_sps = steps * BATCH / (time.perf_counter() - t0)

    net.eval()
    x1 = torch.randn(1, C_IN, H, W)
    lat = []
    with torch.no_grad():
        for _ in range(10):
            net(x1)
        t0 = time.perf_counter()
        while time.perf_counter() - t0 < min_seconds:
            s = time.perf_counter()
            net(x1)
            lat.append(time.perf_counter() - s)
    return train_sps, 1e3 * statistics.median(lat)


def our_figures(bench, threads, reps):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    cmd = [bench, "--benchmark_filter=unet_small", "--benchmark_format=json",
           f"--benchmark_repetitions={reps}", "--benchmark_min_time=0.5",
           "--benchmark_report_aggregates_only=true"]
    out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    res = {}
    for b in json.loads(out)["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b["time_unit"]]
        res[b["run_name"]] = b["real_time"] * scale
    train = BATCH / res["unet_small/train_step_b32/real_time"]
    infer_ms = 1e3 * res["unet_small/infer_b1/real_time"]
    return train, infer_ms


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", default=os.path.join(here, "..", "build-cnn", "bench", "micro_conv"))
    ap.add_argument("--reps", type=int, default=5, help="Google Benchmark repetitions (median used)")
    ap.add_argument("--seconds", type=float, default=3.0, help="PyTorch measuring time per figure")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--ours", action="append", default=[],
                    help="threads:train_samples_per_s:infer_ms instead of running --bench")
    args = ap.parse_args()
    given = {}
    for s in args.ours:
        th, tr, inf = s.split(":")
        given[int(th)] = (float(tr), float(inf))

    rows = []
    for th in [int(v) for v in args.threads.split(",")]:
        ours = given.get(th) or our_figures(args.bench, th, args.reps)
        theirs = torch_figures(th, args.seconds)
        rows.append((th, ours, theirs))

    print(f"torch {torch.__version__} (mkldnn={torch.backends.mkldnn.is_available()}), "
          f"default U-Net 4->2 @ {H}x{W}, train batch {BATCH}, infer batch 1")
    print(f"{'threads':>7} | {'train samples/s':^29} | {'infer latency ms (b=1)':^29}")
    print(f"{'':>7} | {'ours':>8} {'torch':>8} {'ours/torch':>10} | {'ours':>8} {'torch':>8} {'torch/ours':>10}")
    for th, (otr, oinf), (ttr, tinf) in rows:
        print(f"{th:>7} | {otr:8.1f} {ttr:8.1f} {otr / ttr:10.2f} | {oinf:8.3f} {tinf:8.3f} {tinf / oinf:10.2f}")
    print("ratios > 1 mean dc_learning is faster")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Frequency response of live lighting's temporal filter (Havran et al. 2005 §3.3; the taps of
envmap/light_filter.h), printed and normalised: a Markdown table on stdout and a chart.

    /usr/bin/python3 bench/plot_fir_response.py docs/charts/fir-response.png

Debian's python3 with numpy and matplotlib (python3-matplotlib, in .ci/install-deps.sh).
"""
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PRINTED = np.array([0.06216, 0.01296, -0.13816, 0.28315, 0.65223,
                    0.28315, -0.13816, 0.01296, 0.06216])
FS = 21.0  # Hz: the paper's environment-map frame rate


def response(taps, f):
    k = np.arange(len(taps))
    return np.abs(np.exp(-2j * np.pi * np.outer(f, k) / FS) @ taps)


def main():
    normalised = PRINTED / PRINTED.sum()
    print("printed sum %.5f; normalised taps: %s" % (PRINTED.sum(), ", ".join("%.6f" % w for w in normalised)))
    print("\n| f (Hz) | f / fs | gain printed | gain normalised | normalised (dB) |")
    print("|---|---|---|---|---|")
    for f in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 10.5]:
        p, n = response(PRINTED, [f])[0], response(normalised, [f])[0]
        print("| %.1f | %.3f | %.3f | %.3f | %.1f |" % (f, f / FS, p, n, 20 * np.log10(n)))
    f = np.linspace(0, FS / 2, 400)
    plt.figure(figsize=(6, 3.2))
    plt.plot(f, response(PRINTED, f), label="printed taps (sum 1.092)")
    plt.plot(f, response(normalised, f), label="normalised (sum 1)")
    plt.axvspan(7, 9, color="0.9", label="transition 7-9 Hz (paper)")
    plt.xlabel("frequency (Hz), sampling at 21 Hz")
    plt.ylabel("|H(f)|")
    plt.title("Havran 2005 §3.3 FIR, 9 taps")
    plt.legend(fontsize=8)
    plt.grid(alpha=0.3)
    plt.tight_layout()
    plt.savefig(sys.argv[1] if len(sys.argv) > 1 else "fir-response.png", dpi=100)


if __name__ == "__main__":
    main()

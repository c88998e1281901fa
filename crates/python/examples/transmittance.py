"""The data of the transmittance figure (figures/transmittance.png) on the paper scene:
the linear response and the symmetric two-impact orbits on the analytic grid, the simulated
steady state from rest on the compared grid (the grids of `cargo xtask figures`).
Run: python transmittance.py [--plot]   (about 20 s on two cores; --plot needs matplotlib)
"""
import sys

import numpy as np
import rattle

scene = rattle.Scene.paper()
analytic = rattle.sweep(scene, rattle.frequencies(0.1, 4.0, 1561), solver="analytic")
simulated = rattle.sweep(scene, rattle.frequencies(0.1, 4.0, 400), solver="event")
for name, table in (("analytic", analytic), ("simulated", simulated)):
    numbers = {n: c for n, c in table.columns.items() if c.dtype == np.float64}
    np.savetxt(f"transmittance-{name}.csv", np.column_stack(list(numbers.values())),
               delimiter=",", header=",".join(numbers), comments="")

if "--plot" in sys.argv:
    import matplotlib.pyplot as plt

    a, s = analytic, simulated
    plt.plot(a.omega, a.linear_transmittance_db, "k:", label="linear")
    plt.plot(s.omega, s.simulated_transmittance_db, "r+", label="simulated from rest")
    for b in ("branch0", "branch1"):
        ok = getattr(a, f"{b}_stable") & getattr(a, f"{b}_viable")
        plt.plot(a.omega, np.where(ok, getattr(a, f"{b}_transmittance_db"), np.nan), lw=2, label=f"{b}, stable and viable")
    plt.xlabel("ω (rad/s)"); plt.ylabel("T (dB)"); plt.legend(); plt.savefig("transmittance.png", dpi=150)

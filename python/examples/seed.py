"""The seed comparison from Python: the table, the centrelines, and the central film over speed.

    pip install ./python matplotlib
    python python/examples/seed.py            # writes seed_centrelines.png and seed_speed.png

The comparison takes about 10 s on 2 cores; the speed sweep about 3 minutes (each of its four
points on the grid its accuracy needs, checked on coarser grids and a longer inlet).
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import ehl

# Every model of the seed on the grid an accuracy of 5 % needs (449²), each answer with its
# estimated error; a flagged answer would warn (ehl.AccuracyWarning) and list why in c.flagged.
c = ehl.compare("seed", accuracy=0.05)
print(c.table())  # the table the command line prints; pandas.DataFrame(c.table()) takes its rows
assert not c.flagged, c.flagged

fig, (ax_p, ax_h) = plt.subplots(1, 2, figsize=(11, 4))
for model, r in c.results.items():
    j = r.y.size // 2  # the centre line y = 0
    x_mm = r.x * 1e3
    ax_p.plot(x_mm, r.pressure[j] / 1e9, label=model)
    ax_h.plot(x_mm, r.film[j] * 1e9, label=model)
for model, why in c.errors.items():
    print(f"{model} failed: {why}")
ax_p.set(xlabel="x [mm]", ylabel="p [GPa]", title="Pressure along y = 0")
ax_h.set(xlabel="x [mm]", ylabel="h [nm]", title="Film along y = 0", ylim=(0, 60))
ax_p.legend()
fig.tight_layout()
fig.savefig("seed_centrelines.png", dpi=120)

# The central film over speed: a sweep (every point checked against a finer grid), as rows.
speeds = [0.005, 0.01, 0.02, 0.05]
s = ehl.sweep(
    {
        "name": "speed",
        "scene": "seed",
        "parameters": [{"parameter": "conditions.rolling_velocity_m_s", "values": speeds}],
    }
)
rows = [r for r in s.table() if r["converged"]]
fig, ax = plt.subplots(figsize=(6, 4))
for model in ("layer", "reynolds", "reynolds-flooded"):
    pts = [
        (r["conditions.rolling_velocity_m_s"], r["central_film_m"] * 1e9) for r in rows if r["model"] == model
    ]
    if pts:
        ax.loglog(*zip(*pts), "o-", label=model)
ax.set(xlabel="u1 [m/s]", ylabel="h_c [nm]", title="Central film over speed (seed, 25 nm supplied)")
ax.legend()
fig.tight_layout()
fig.savefig("seed_speed.png", dpi=120)
print(f"sweep files in {s.folder}; figures seed_centrelines.png, seed_speed.png")

# %% [markdown]
# # gfmd in Python: from Hertz to leakage
#
# Run top to bottom (`/usr/bin/python3 examples/python/tutorial.py`, or cell by cell in an
# editor that knows `# %%`). Units: lengths in L (the cell's lx), pressures in E*, forces in
# E* L^2. Figures go to out/tutorial/.
# %%
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import gfmd  # noqa: E402

OUT = os.path.join("out", "tutorial")
os.makedirs(OUT, exist_ok=True)

# %% [markdown]
# ## 1. Hertz: a sphere pressed on a half-space
# Radius R = 1, force F = 0.01 E* R^2. Hertz: contact radius a = (3 F R / 4 E*)^(1/3).
# %%
sphere = gfmd.Topography.hertz(nx=256, lx=1.6, radius=1.0)
half_space = gfmd.ElasticBody(poisson=0.25)
r = gfmd.solve(sphere, half_space, force=0.01)
a_hertz = (3 * 0.01 / 4) ** (1 / 3)
a_num = math.sqrt(r.summary["relative_contact_area"] * 1.6 ** 2 / math.pi)
print(f"contact radius: gfmd {a_num:.4f}, Hertz {a_hertz:.4f}")
r.plot("pressure").figure.savefig(os.path.join(OUT, "hertz_pressure.png"), dpi=120)

# %% [markdown]
# ## 2. A rough surface
# Self-affine, Hurst 0.8, wavelengths from lx/2 down to lx/64, rms height 0.01 L.
# %%
rough = gfmd.Topography.self_affine(nx=256, lx=1.0, hurst=0.8, lambda_long=0.5, lambda_short=1 / 64,
                                    rms_height=0.01, seed=1)
print(rough, "rms gradient", round(rough.rms_gradient(), 4))
q, c = rough.psd()
plt.figure()
plt.loglog(q, c, ".")
plt.xlabel("q (1/L)")
plt.ylabel("C(q) (L^4)")
plt.savefig(os.path.join(OUT, "rough_psd.png"), dpi=120)
r = gfmd.solve(rough, half_space, pressure=0.02)
print("relative contact area", r.summary["relative_contact_area"])

# %% [markdown]
# ## 3. Sliding with friction on a thin, nearly incompressible layer
# The coupling between normal and in-plane displacements changes friction (the paper's point):
# compare the macroscopic friction coefficient with the local one, mu_c = 1.
# %%
layer = gfmd.ElasticBody(poisson=0.49, thickness=0.1)
s = gfmd.solve(rough, layer, pressure=0.02, friction=1.0, progress=lambda it, step, ch: None)
print(f"mu = {s.summary['friction_coefficient']:.4f} (mu_c = 1); dmu/mu_c = {s.summary['delta_mu_over_mu_c']:+.4f}")
s.plot("dissipation").figure.savefig(os.path.join(OUT, "rough_dissipation.png"), dpi=120)

# %% [markdown]
# ## 4. Surface and subsurface stresses
# sigma_1 is the most tensile principal stress at the surface; von Mises at depth 0.01 L.
# %%
s = gfmd.solve(rough, layer, pressure=0.02, friction=1.0, stress_depths=[0.01])
print("max tensile stress", s.summary["max_tensile_stress"], "at", s.summary["max_tensile_stress_location"])
print("max von Mises at depth 0.01:", s.summary["subsurface"][0]["max_von_mises"])
s.plot("sigma_1", cmap="RdBu_r").figure.savefig(os.path.join(OUT, "rough_sigma1.png"), dpi=120)

# %% [markdown]
# ## 5. Leakage through the deformed gap
# Reynolds flow with local conductivity g^3; flow_factor = K_eff / <g>^3.
# %%
flow = s.flow(("x", "y"))
print({k: round(flow["summary"][k], 4) for k in ("flow_factor_x", "flow_factor_y")})
fig, ax = plt.subplots()
im = ax.imshow(np.log10(flow["fields"]["current_x"] + 1e-30), origin="lower", extent=(0, 1, 0, 1))
fig.colorbar(im, ax=ax, label="log10 |current| (x-flow)")
ax.set_xlabel("x (L)")
ax.set_ylabel("y (L)")
fig.savefig(os.path.join(OUT, "rough_current.png"), dpi=120)

# %% [markdown]
# ## 6. Keep the run
# The same directory `gfmd run` writes: summary.json, fields.nc, profiles.csv.
# %%
s.save(os.path.join(OUT, "rough_run"))
print("written", sorted(os.listdir(os.path.join(OUT, "rough_run"))))

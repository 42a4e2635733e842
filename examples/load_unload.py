# %% [markdown]
# # A load-unload path
#
# The elastoplastic cylinder of `cases/hertz_load_unload.toml` (Sy = 200 MPa, H' = 700 MPa,
# mu = 0.3): stage "load" takes P from 0 to 1000 N/mm (path time t in [0, 1]), stage "unload"
# back to 0 (t in [1, 2]).  Every yield and every elastic unloading of an element is an event;
# the snapshots (one per event here) carry the path time t.

# %%
import numpy as np

import slipstep

r = slipstep.run("hertz_load_unload", out="results/hertz_load_unload")
r  # noqa: B018

# %% [markdown]
# Events by kind and stage, from the structured array `r.events` (a `pandas.DataFrame(r.events)`
# works too):

# %%
ev = r.events
for stage in (1, 2):
    kinds, counts = np.unique(ev["kind"][ev["stage"] == stage], return_counts=True)
    print(f"stage {stage}: " + ", ".join(f"{n} {k}" for k, n in zip(kinds, counts)))

# %% [markdown]
# At the peak load (t = 1, the end of stage 1: at t = 1 the path also holds the start of stage 2,
# where the plastic elements have switched to unloading) and after unloading (t = 2): contact
# force, plastic zone, and the plastic strain that stays.

# %%
for t, stage in ((1.0, 1), (2.0, 2)):
    f = r.fields(t, stage=stage)
    print(
        f"t = {t}: total normal force {f['lambda_n'].sum():.3f} N/mm, "
        f"{int(f['plastic'].sum())} elements on the yield surface, "
        f"{int((f['plastic_strain'] > 0).sum())} with plastic strain, "
        f"max plastic strain {f['plastic_strain'].max():.3e}"
    )

# %% [markdown]
# The figures as matplotlib objects (drawn without pyplot, so a notebook's own figures and
# backend are untouched): `fig.savefig(...)` anywhere; in Jupyter, `r.figures()["contact_extent"]`
# as a cell's value shows inline once the inline backend is active (`%matplotlib inline`, or
# any earlier `import matplotlib.pyplot`).

# %%
figs = r.figures()
print(sorted(figs), "-", figs["contact_extent"].axes[0].get_ylabel())

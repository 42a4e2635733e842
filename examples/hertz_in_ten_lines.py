# %% [markdown]
# # Hertz in ten lines
#
# The built-in elastic cylinder (R = 125 mm, E = 70 GPa, nu = 0.3, P = 1000 N/mm, plane
# strain, quarter model) on a rigid flat, solved event by event, against Hertz (Johnson,
# Contact Mechanics §4.3).  A percent-format script: run it with python, or open it in
# Jupyter as a notebook (jupytext), where `r` shows a summary table.

# %%
import math

import slipstep

r = slipstep.run("hertz_cylinder", overrides=["mesh.h_contact=0.05"])
a = math.sqrt(4 * 1000.0 * 125.0 / (math.pi * 70000.0 / (1 - 0.3**2)))  # Hertz, E* plane strain
print(f"a  = {r.summary['contact_half_width']:.4f} mm (Hertz {a:.4f})")
print(f"p0 = {r.summary['peak_pressure']:.1f} MPa (Hertz {2 * 1000.0 / (math.pi * a):.1f})")
for t in (0.5, 1.0):  # the contact force balances the load P/2 on the quarter model
    print(f"t = {t}: total normal force {r.fields(t)['lambda_n'].sum():.3f} N/mm")
r  # noqa: B018 - the summary

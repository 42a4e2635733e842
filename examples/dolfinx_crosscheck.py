# %% [markdown]
# # A dolfinx cross-check
#
# The thick-walled cylinder (a = 10, b = 20 mm, internal pressure 175 MPa, Sy = 250 MPa,
# perfectly plastic, plane strain) solved by slipstep event by event and by dolfinx with N
# equal load steps of Newton on the identical mesh (`slipstep.fenicsx.crosscheck`, Debian's
# dolfinx 0.5.2), both against Hill's closed form for the plastic radius c.

# %%
import json
from pathlib import Path

from slipstep import shipped
from slipstep.fenicsx import crosscheck

out = Path("results/thick_cylinder_crosscheck")
report = crosscheck.run(
    shipped.path("thick_cylinder"), out, overrides=["mesh.h=1.0"], steps=(5, 10)
)

# %%
for row in report["rows"]:
    print(f"{row['what']}: relative difference u {row['u']:.2e}, stress {row['stress']:.2e}")
hill = report["hill"]
print(
    f"plastic radius: slipstep {hill['slipstep']['plastic_radius']:.3f} mm, dolfinx "
    f"{hill['dolfinx']['plastic_radius']:.3f} mm, Hill {hill['slipstep']['hill_c']:.3f} mm"
)
print(json.dumps({"report": str(out / "crosscheck.md")}))

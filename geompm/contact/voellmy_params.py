"""What a rigid surface declares for Voellmy friction (contact/voellmy.py): the turbulent coefficient and the
flow's density; mu is the surface's ``friction``."""

from __future__ import annotations

from pydantic import Field, model_validator

from geompm.contract.plugin import Params


class VoellmyParams(Params):
    xi: float | None = Field(
        None, gt=0.0, description="Voellmy's turbulent coefficient xi [m/s2] (condition 'voellmy'; RAMMS and "
                                  "r.avaflow call it xi too; typical 100-2000 m/s2): tau = mu sigma_n + rho g u^2 / xi")
    density: float | None = Field(
        None, gt=0.0, description="rho [kg/m3] of the turbulent term (condition 'voellmy'); default the materials' "
                                  "density when they share one")

    @model_validator(mode="after")
    def _voellmy(self):
        if getattr(self, "condition", None) == "voellmy" and self.xi is None:
            raise ValueError("condition 'voellmy' needs 'xi' [m/s2] (and 'friction', Voellmy's mu)")
        if getattr(self, "condition", None) != "voellmy" and (self.xi is not None or self.density is not None):
            raise ValueError("'xi' and 'density' belong to condition 'voellmy'; set \"condition\": \"voellmy\" or "
                             "remove them")
        return self


def flow_density(params, scene, label: str) -> float:
    """The turbulent term's rho: ``density``, else the materials' common density (CaseError if they differ)."""
    from geompm.errors import CaseError

    if params.density is not None:
        return float(params.density)
    rhos = sorted({float(m.density) for m in scene.materials})
    if len(rhos) > 1:
        raise CaseError([(label, f"the materials' densities differ ({', '.join(f'{r:g}' for r in rhos)} kg/m3): give "
                                 "the Voellmy friction's 'density' [kg/m3]")])
    return rhos[0]


def voellmy_slots(params, rho: float | None, g: float, h: float, d: int, layer: float) -> dict:
    """The packed Voellmy entries of a surface (contact/voellmy.py): xi [m/s2], the node drag rho g h^(d-1)
    and the lowest signed distance of the nodes that take it, layer - h [m]; zeros unless 'voellmy' (rho:
    flow_density's, None otherwise)."""
    slots = {"xi": 0.0, "drag": 0.0, "band": layer - h}
    if params.condition == "voellmy":
        slots.update(xi=params.xi, drag=rho * g * h ** (d - 1))
    return slots


def voellmy_density(params, scene, label: str) -> float | None:
    """flow_density for a surface whose condition is 'voellmy', None otherwise."""
    return flow_density(params, scene, label) if params.condition == "voellmy" else None

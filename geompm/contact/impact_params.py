"""What a contact surface with a force history declares for its impact quantities (contact/impact.py)."""

from __future__ import annotations

from pydantic import Field

from geompm.contract.plugin import Params


class ImpactParams(Params):
    force_window: float | None = Field(
        None, gt=0.0, description="Length of the moving average of the force [s] whose peak is the filtered peak "
        "force (contact/impact.py); default a tenth of the time from the start to first contact "
        "(docs/impact-forces.md)")
    probe: str | None = Field(
        None, description="Name of a probe of the case (probes[].name) upstream of this surface: its flow depth, "
        "speed and density (when its momentum flux rho v^2 h was largest, up to one force window after first contact) give the equivalent coefficients alpha = F / (rho v^2 h w) and "
        "k = F / (rho g h^2 w / 2) of the filtered peak")
    design_width: float | None = Field(
        None, gt=0.0, description="Width w of the surface facing the flow [m] in alpha and k (3D); default the "
        "extent of its bounding box across the flow (horizontal, normal to the flow's direction at the probe); "
        "2D forces are per metre (w = 1 m)")

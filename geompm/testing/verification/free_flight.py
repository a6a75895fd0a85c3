"""A linear-elastic block in free flight (no gravity, no wall) at 3 m/s: its kinetic energy must stay as it is
(benchmarks/envelope/free_flight.py; tests/verification/test_pore_water_transfer.py)."""


def block_case(shape: str, transfer: str, saturated: bool, length: float = 5.0, end: float = 1.0) -> dict:
    """A 0.4 m square block (rho = 2000 kg/m3, E = 10 MPa) at 3 m/s along x in a grid ``length`` m long, h =
    0.05 m; ``saturated``: n = 0.4, k = 1e-8 m/s, K_w = 2.2e7 Pa (grains of the same density)."""
    soil = {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 10e6, "poisson_ratio": 0.3}
    if saturated:
        soil["pore_water"] = {"porosity": 0.4, "hydraulic_conductivity": 1e-8, "fluid": {"bulk_modulus": 2.2e7}}
    return {"name": "free_flight", "dimension": 2,
            "grid": {"origin": [0, 0], "extent": [length, 1], "cell_size": 0.05, "shape_function": shape},
            "time": {"end": end}, "gravity": [0, 0], "materials": {"soil": soil},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.2, 0.3], "max": [0.6, 0.7]},
                        "velocity": [3, 0], "particles_per_cell": 2}],
            "solver": {"transfer": transfer}}

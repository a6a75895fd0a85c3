"""The numerical envelope: small scenes at the extremes of each parameter (docs/numerical-envelope.md), with the
harness that runs them and the biaxial test of a dilatant sample."""

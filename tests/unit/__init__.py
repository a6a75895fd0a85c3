"""Unit tests: one function, kernel or contract at a time (shape functions, transfers against the generic
reference, the eigen-solver, the sort, the law and stage contracts, case validation), each against an
exact or closed-form answer."""

"""Validation harness: lecture derivations of *Mathematical Modeling* against Pinocchio and MuJoCo."""

"""The machine: chain-spec facts and the geometry API on the generated kinematics (Machine, load_machine)."""

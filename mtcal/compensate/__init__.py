"""First-order compensation of NC programs against an error model."""

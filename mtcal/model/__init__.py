"""The error model: ErrorModel and its error functions (mm, rad), the JSON schema, the plausibility guard."""

"""Generated code (do not edit): see manifest.json and derive/ for how it was made."""

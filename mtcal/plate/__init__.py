"""Hocken-Borchardt 2-D plate reversal (NBSIR 79-1752)."""

"""Campaign plans and the physical simulator: planted effects as physics, one or several tracker stations
(mm, deg, s; machine frame)."""
from mtcal.campaign.plans import Plan, as_plan, load_plan
from mtcal.campaign.simulate import simulate, simulate_campaign

__all__ = ["Plan", "as_plan", "load_plan", "simulate", "simulate_campaign"]

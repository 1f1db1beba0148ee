"""Thermal tests and thermal error models: a thermal test read as it comes (readings), the ISO 230-3 evaluations
(iso230_3), the thermal vocabulary shared with the diagnosis (features), a model from the temperatures and the
spindle speed's history to each drift channel, judged out of sample in time (model), plots."""
from mtcal.thermal.features import first_order_lag, recording_rise, temperature_rise, warm_up
from mtcal.thermal.model import ThermalModel, fit_thermal, model_from_dict
from mtcal.thermal.readings import ThermalTest, read_thermal_test

__all__ = ["ThermalModel", "ThermalTest", "first_order_lag", "fit_thermal", "model_from_dict", "read_thermal_test",
           "recording_rise", "temperature_rise", "warm_up"]

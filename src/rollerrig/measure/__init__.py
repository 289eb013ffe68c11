"""Measurements: DAQ recordings, channel maps, physical quantities, test segmentation."""

"""rollerrig.report"""

"""rollerrig.contact"""

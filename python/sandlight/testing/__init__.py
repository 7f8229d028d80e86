"""Public helpers for testing sandlight and code built on it: analytic references and checks.

Modules
-------
chandrasekhar
    Chandrasekhar's H-function and the exact BRDF of a half-space of isotropic scatterers.
"""

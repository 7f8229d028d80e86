"""Public helpers for testing sandlight and code built on it: analytic references and checks.

Modules
-------
chandrasekhar
    Chandrasekhar's H-function and the exact BRDF of a half-space of isotropic scatterers.
chi2
    Chi-square test of a sampler of hemisphere directions against its pdf.
synthetic_brdf
    Virtual-goniophotometer counts drawn from a known BRDF (Lambertian, Chandrasekhar, any
    azimuth-independent one), to test the reduction pipeline.
"""

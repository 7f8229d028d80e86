"""Physics of a sand sample: from measurable parameters to the particle populations and the
per-wavelength optical medium the transport engine traces (docs/transport.md)."""

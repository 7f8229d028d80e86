"""Sand in Mitsuba 3: the `sand` BSDF plugin, example scenes and animations (docs/mitsuba.md).

Install with ``pip install 'sandlight[mitsuba]'``; the llvm variants also need LLVM ≥ 16
(``apt-get install libllvm19`` on Debian; `configure_llvm` finds it).

>>> import sandlight.mitsuba as sm                                          # doctest: +SKIP
>>> mi = sm.load_mitsuba("llvm_ad_spectral")        # sets the variant and registers "sand"
>>> bsdf = mi.load_dict({"type": "sand", "preset": "wet-beach"})

Modules
-------
parameters
    The plugin's parameters (`SandSpec`), checked, and the appearances they build.
tables
    `PluginTables`: the appearances' arrays, and the RGB variants' conversion.
bsdf
    The plugin class, in Dr.Jit array operations.
llvm
    Locating the LLVM library of the llvm variants.
scenes
    Example scenes (Python dicts and XML) for the desert and the drying beach.
animation
    The paper's two animations rendered through Mitsuba.
"""

from __future__ import annotations

from types import ModuleType

from sandlight.errors import ParameterError, SandlightError
from sandlight.mitsuba.llvm import configure_llvm, find_libllvm
from sandlight.mitsuba.parameters import PLUGIN_NAME, PluginParameterError, SandSpec

__all__ = [
    "MitsubaUnavailable",
    "PLUGIN_NAME",
    "PluginParameterError",
    "SandSpec",
    "configure_llvm",
    "find_libllvm",
    "load_mitsuba",
    "register",
    "SUPPORTED_PREFIXES",
]

#: Variant families the plugin supports (JIT variants: the plugin is traced into kernels).
SUPPORTED_PREFIXES = ("llvm_ad_", "cuda_ad_", "llvm_", "cuda_")


class MitsubaUnavailable(SandlightError, ImportError):
    """Mitsuba is not installed, or the variant cannot start (no LLVM for the llvm variants)."""


def register() -> None:
    """Register the `sand` BSDF in the current Mitsuba variant (again after each ``set_variant``).

    Raises
    ------
    ParameterError
        No variant is set, or it is a scalar or polarised variant.
    """
    import mitsuba as mi
    from sandlight.mitsuba.bsdf import bsdf_class

    variant = mi.variant()
    if variant is None or not variant.startswith(SUPPORTED_PREFIXES) or "polarized" in variant:
        raise ParameterError(
            "variant",
            variant,
            "a JIT, unpolarised Mitsuba variant (llvm_ad_rgb, llvm_ad_spectral, llvm_ad_mono, cuda_…)",
        )
    cls = bsdf_class(variant)
    mi.register_bsdf(PLUGIN_NAME, lambda props: cls(props))


def load_mitsuba(variant: str = "llvm_ad_rgb") -> ModuleType:
    """Import Mitsuba (after `configure_llvm`), set ``variant`` and `register` the plugin.

    Raises
    ------
    ParameterError
        ``variant`` is not one Mitsuba offers here, or not supported by the plugin.
    MitsubaUnavailable
        Mitsuba is not installed (``pip install 'sandlight[mitsuba]'``), or the variant does not
        start (the llvm variants need LLVM ≥ 16: ``apt-get install libllvm19``).
    """
    configure_llvm()
    try:
        import mitsuba as mi
    except ImportError as e:
        raise MitsubaUnavailable(f"sandlight.mitsuba needs Mitsuba 3 ({e}): pip install 'sandlight[mitsuba]'") from e
    if variant not in mi.variants():
        raise ParameterError("variant", variant, f"one of {mi.variants()}")
    try:
        mi.set_variant(variant)
    except (ImportError, RuntimeError, AttributeError) as e:
        raise MitsubaUnavailable(
            f"Mitsuba variant {variant!r} does not start ({e}); llvm variants need LLVM >= 16 "
            "(apt-get install libllvm19, or set DRJIT_LIBLLVM_PATH)"
        ) from e
    register()
    return mi

#!/usr/bin/env python3
"""Write the Mitsuba XML examples shipped in ``python/sandlight/data/mitsuba/`` from the shipped
sandlight scenes: ``desert.xml`` (desert-day at 09:00 on the paper's flat plane) and
``beach.xml`` with ``beach-saturation.png`` (beach-drying at 13:00, the saturation map of that
hour as an 8-bit grey image read raw, value/255).

    python3 scripts/mitsuba/make_examples.py [--out python/sandlight/data/mitsuba]

Render one with ``mitsuba -m llvm_ad_spectral`` after registering the plugin, e.g.
``python3 -c "import sandlight.mitsuba as s; mi = s.load_mitsuba('llvm_ad_spectral');
mi.util.write_bitmap('beach.exr', mi.render(mi.load_file(str(s.scenes.example_xml_path('beach.xml')))))"``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
WIDTH, HEIGHT, SPP = 320, 180, 64


def _sensor(camera, spp: int) -> str:
    o, t = camera.position, camera.position + camera.forward
    return f"""    <sensor type="perspective">
        <float name="fov" value="{camera.fov_deg:g}"/>
        <string name="fov_axis" value="x"/>
        <transform name="to_world">
            <lookat origin="{o[0]:.6g}, {o[1]:.6g}, {o[2]:.6g}"
                    target="{t[0]:.6g}, {t[1]:.6g}, {t[2]:.6g}" up="0, 0, 1"/>
        </transform>
        <sampler type="independent"><integer name="sample_count" value="{spp}"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="{camera.width}"/>
            <integer name="height" value="{camera.height}"/>
            <rfilter type="box"/>
        </film>
    </sensor>"""


def _sky(sun, turbidity: float) -> str:
    return f"""    <emitter type="sunsky">
        <vector name="sun_direction" x="{sun[0]:.6f}" y="{sun[1]:.6f}" z="{sun[2]:.6f}"/>
        <float name="turbidity" value="{turbidity:g}"/>
    </emitter>"""


def _ground(bsdf: str, half_size_m: float = 2000.0, z_m: float = 0.0) -> str:
    return f"""    <shape type="rectangle">
        <transform name="to_world">
            <scale x="{half_size_m:g}" y="{half_size_m:g}" z="1"/><translate z="{z_m:g}"/>
        </transform>
{bsdf}
    </shape>"""


def _far(bsdf: str) -> str:
    """The far plane 1 cm below (sandlight.mitsuba.scenes.FAR_HALF_SIZE_M): ground to the horizon."""
    return _ground(bsdf, 1.0e6, -0.01)


def _scene(title: str, body: list[str], max_depth: int) -> str:
    return (
        f'<?xml version="1.0" encoding="utf-8"?>\n<!-- {title}\n     Written by scripts/mitsuba/make_examples.py; '
        'needs the "sand" plugin (import sandlight.mitsuba; docs/mitsuba.md). -->\n'
        f'<scene version="3.0.0">\n    <integrator type="path"><integer name="max_depth" value="{max_depth}"/>'
        "</integrator>\n" + "\n".join(body) + "\n</scene>\n"
    )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "python" / "sandlight" / "data" / "mitsuba")
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "python"))
    import sandlight.mitsuba as sm
    from sandlight.mitsuba.scenes import saturation_texture
    from sandlight.render import PlaneTerrain, Scene, post

    mi = sm.load_mitsuba("llvm_ad_rgb")
    args.out.mkdir(parents=True, exist_ok=True)

    desert = Scene.load("desert-day").with_overrides(width=WIDTH, height=HEIGHT)
    camera = desert.build_camera(PlaneTerrain(0.0))
    bsdf = '        <bsdf type="sand"><string name="preset" value="yellow-dune"/></bsdf>'
    xml = _scene(
        "desert-day at 09:00 solar time (25 N, 20 April) on the paper's flat plane, under Mitsuba's sunsky",
        [_sensor(camera, SPP), _sky(desert.sun_direction(9.0), desert.sun.turbidity), _ground(bsdf), _far(bsdf)],
        2,
    )
    (args.out / "desert.xml").write_text(xml, encoding="utf-8")

    beach = Scene.load("beach-drying").with_overrides(width=WIDTH, height=HEIGHT)
    frame = int(np.argmin(np.abs(beach.times_h() - 13.0)))
    material = beach.build_material(float(beach.day_fractions()[frame]))
    png = args.out / "beach-saturation.png"
    grey = np.repeat(material.values[:, :, None], 3, axis=2)
    post.write_png(png, grey)  # 8-bit, row j at y0 + j·dy (Mitsuba's uv.y follows the rows)
    texture = saturation_texture(mi, material)
    m = np.array(texture["to_uv"].matrix).reshape(4, 4)
    matrix = " ".join(f"{v:.9g}" for v in m.ravel())
    bsdf = f"""        <bsdf type="sand">
            <string name="preset" value="wet-beach"/>
            <texture name="saturation" type="bitmap">
                <string name="filename" value="beach-saturation.png"/>
                <boolean name="raw" value="true"/>
                <string name="wrap_mode" value="clamp"/>
                <transform name="to_uv"><matrix value="{matrix}"/></transform>
            </texture>
            <integer name="levels" value="{beach.levels.size}"/>
        </bsdf>"""
    cam = beach.build_camera(PlaneTerrain(0.0))
    ahead = cam.position[:2] + 1e7 * cam.forward[:2]
    far = (
        '        <bsdf type="sand"><string name="preset" value="wet-beach"/>'
        f'<float name="saturation" value="{float(material.value_at(ahead[0], ahead[1])):.6g}"/></bsdf>'
    )
    xml = _scene(
        f"beach-drying at {beach.times_h()[frame]:.0f}:00 (36 N, 19 July): saturation from beach-saturation.png "
        "(the scene's waterline map of that hour), under Mitsuba's sunsky",
        [
            _sensor(cam, SPP),
            _sky(beach.sun_direction(float(beach.times_h()[frame])), beach.sun.turbidity),
            _ground(bsdf),
            _far(far),
        ],
        2,
    )
    (args.out / "beach.xml").write_text(xml, encoding="utf-8")
    print(
        f"wrote {args.out / 'desert.xml'}, {args.out / 'beach.xml'}, {png} "
        f"({material.values.shape[1]}×{material.values.shape[0]} px)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())

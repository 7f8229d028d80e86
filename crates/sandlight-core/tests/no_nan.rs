//! Hunts for NaN or non-unit directions and lost rays over extreme but valid media.

use sandlight_core::driver::incident_direction;
use sandlight_core::medium::{ParticleType, Particulate};
use sandlight_core::particle::{Coating, ParticleOptics, PoreOptics};
use sandlight_core::rng::Rng;
use sandlight_core::sizes::QuantileTable;
use sandlight_core::transport::{Fate, Limits, Medium};

fn medium(aspect: f64, k: f64, alpha: f64, coating: Option<Coating>, film: f64, filled: f64) -> Particulate {
    let t = |p: f64, d: f64, n: f64| ParticleType {
        probability: p,
        sizes: QuantileTable::new(vec![d * 0.5, d, d * 2.0]).unwrap(),
        aspect_ratio: aspect,
        optics: ParticleOptics {
            core_n: n,
            core_k: k,
            core_alpha_per_mm: alpha,
            core_scattering_per_mm: 0.0,
            coating,
            wets: true,
        },
    };
    let pore = PoreOptics {
        water_n: 1.333,
        water_alpha_per_mm: 0.01,
        film_thickness_mm: film,
        film_coverage: 0.6,
        water_filled_probability: filled,
    };
    Particulate::new(vec![t(0.6, 0.25, 1.544), t(0.3, 0.001, 1.56), t(0.1, 0.01, 2.4)], 0.1, pore, f64::INFINITY)
        .unwrap()
}

#[test]
fn every_escaped_direction_is_a_finite_upward_unit_vector() {
    let coat = Some(Coating::uniform(1.9, 200.0, 0.0005));
    // Partial coatings (bare surface between patches), absorbing and pigmented.
    let patchy = Some(Coating { coverage: 0.3, ..Coating::uniform(2.4, 3e4, 0.002) });
    let pigment_patches =
        Some(Coating { scattering_per_mm: 2e4, asymmetry: 0.6, coverage: 0.5, ..Coating::uniform(1.9, 200.0, 0.0005) });
    let media = [
        medium(1.0, 0.0, 0.01, None, 0.0, 0.0),
        medium(3.0, 1.3, 3e4, coat, 0.0, 0.0),
        medium(2.2, 1e-4, 1.0, coat, 0.002, 0.0),
        medium(1.4, 0.0, 0.05, None, 0.001, 0.9),
        medium(3.0, 0.0, 0.0, coat, 0.0, 1.0),
        medium(1.7, 1e-4, 1.0, patchy, 0.002, 0.3),
        medium(2.5, 0.0, 0.05, pigment_patches, 0.001, 0.0),
    ];
    let limits = Limits { max_events: 100_000, max_internal: 10_000 };
    for (mi, m) in media.iter().enumerate() {
        for theta_deg in [0.0f64, 45.0, 89.9] {
            let d = incident_direction(theta_deg.to_radians());
            for i in 0..3000u64 {
                let mut rng = Rng::for_ray(mi as u64, 0, i);
                let out = m.trace(d, &mut rng, &limits);
                if let Fate::Escaped(v) = out.fate {
                    assert!(v.is_finite(), "NaN direction, medium {mi}, θ {theta_deg}, ray {i}");
                    assert!((v.norm2() - 1.0).abs() < 1e-9, "non-unit direction {v:?}");
                    assert!(v.z >= 0.0, "escaped downwards {v:?}");
                }
            }
        }
    }
}

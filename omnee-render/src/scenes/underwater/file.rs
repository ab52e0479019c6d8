//! The underwater scene file: TOML with every parameter, validated field by
//! field; every error names the field (`section.key`), its value and the
//! allowed range. The built-in scene is `scenes/underwater.toml`, which
//! documents every field.

use super::sun::Sun;
use super::surface::{Surface, Wave, WaveKind};
use super::transport::{ShaftSampling, UNDERWATER_TERMS};
use super::water::Water;
use crate::error::{RenderError, Result};
use crate::phase::PhaseSpec;
use crate::range::Range;
use crate::scenes::floor::{Floor, FloorPattern};
use crate::section::Section;
use glam::{Vec2, Vec3};
use omnee_core::method::{Choice, LobeMethod};
use omnee_core::names::Named;
use omnee_core::rng::SplitMix64;

/// The built-in underwater scene, as shipped in `omnee-render/scenes/underwater.toml`.
pub const UNDERWATER_SCENE: &str = include_str!("../../../scenes/underwater.toml");

/// The camera as given.
#[derive(Clone, Debug)]
pub struct CameraSpec {
    /// Eye position.
    pub position: Vec3,
    /// Target.
    pub look_at: Vec3,
    /// Up direction.
    pub up: Vec3,
    /// Vertical field of view (radians).
    pub fov: f32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
}

/// The techniques of `caustics-once-more`: OMNEE, equiangular from a
/// camera ray, their combination, and `auto` ([`super::choose_technique`]).
pub const UNDERWATER_TECHNIQUES: [Choice; 4] = [
    Choice::Omnee,
    Choice::Equiangular,
    Choice::Mis,
    Choice::Auto,
];

/// The techniques of `shafts-once-more`, whose `x0` has the phase
/// function's lobe about the refracted sun ray.
pub const SHAFT_TECHNIQUES: [Choice; 2] = [Choice::Omnee, Choice::LobeMis];

/// Render settings stored in the scene (command-line options override them).
#[derive(Clone, Debug)]
pub struct UnderwaterSettings {
    /// Passes of `width · height` light paths.
    pub spp: u32,
    /// Random seed.
    pub seed: u64,
    /// The terms to evaluate, in layer order ([`UNDERWATER_TERMS`]).
    pub terms: [bool; 4],
    /// The once-more technique, one of [`UNDERWATER_TECHNIQUES`].
    pub technique: Choice,
    /// The once-more integrand's restriction θ < θmax (radians).
    pub theta_max: f64,
    /// The mis companion's rate.
    pub mis_rate: f64,
    /// The mis companion's cone edge θmin (radians).
    pub mis_theta_min: f64,
    /// How the shafts' vertex is placed.
    pub shafts: ShaftSampling,
    /// The technique for `shafts-once-more`'s vertex `x1`.
    pub shafts_once_more: LobeMethod,
    /// Once-more draws per floor point.
    pub once_more_samples: u32,
    /// Shaft vertices for a refracted sun ray whose image spans the field of
    /// view; proportionally fewer (at least one) for shorter ones.
    pub shaft_samples: u32,
    /// Growth of the start density's core region around what the camera
    /// sees (m): where paths go, never the image's mean.
    pub margin: f64,
    /// How far from the eye the core region reaches (m), and the longest
    /// tail length of the start density: where paths go, never the mean.
    pub max_distance: f64,
    /// Share of light paths aimed through the image (the rest minus
    /// `eye_share` start from the defensive density, over the whole plane).
    pub camera_share: f64,
    /// Share of light paths aimed past the eye.
    pub eye_share: f64,
    /// The largest distance from the eye of those paths' beams (m).
    pub eye_radius: f64,
    /// PNG exposure in stops; `None` picks it from the image.
    pub exposure: Option<f64>,
}

/// A whole underwater scene.
#[derive(Clone, Debug)]
pub struct UnderwaterScene {
    /// The sun.
    pub sun: Sun,
    /// The water surface.
    pub surface: Surface,
    /// The water's refractive index.
    pub ior: f32,
    /// The water's coefficients.
    pub water: Water,
    /// The phase function.
    pub phase: PhaseSpec,
    /// The floor.
    pub floor: Floor,
    /// The camera.
    pub camera: CameraSpec,
    /// Render settings.
    pub render: UnderwaterSettings,
}

fn input(msg: String) -> RenderError {
    RenderError::Input(msg)
}

/// `[x, y, z]` in f32.
fn vec3([x, y, z]: [f64; 3]) -> Vec3 {
    Vec3::new(x as f32, y as f32, z as f32)
}

/// The surface's kind (`surface.kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SurfaceKind {
    /// No waves.
    Flat,
    /// A height field sum of sines.
    Sine,
    /// Trochoidal waves.
    Gerstner,
}

impl Named for SurfaceKind {
    const ALL: &'static [Self] = &[SurfaceKind::Flat, SurfaceKind::Sine, SurfaceKind::Gerstner];
    fn name(self) -> &'static str {
        match self {
            SurfaceKind::Flat => "flat",
            SurfaceKind::Sine => "sine",
            SurfaceKind::Gerstner => "gerstner",
        }
    }
    fn help(self) -> &'static str {
        match self {
            SurfaceKind::Flat => "no waves",
            SurfaceKind::Sine => "a height field sum of sines",
            SurfaceKind::Gerstner => "trochoidal waves",
        }
    }
}

const UNIT: Range = Range::closed(0.0, 1.0);
const SECTIONS: [&str; 6] = ["sun", "surface", "water", "floor", "camera", "render"];

impl UnderwaterScene {
    /// The built-in scene.
    pub fn builtin() -> Self {
        Self::parse(UNDERWATER_SCENE).expect("the built-in underwater scene is valid")
    }

    /// Parses and validates a scene from TOML text.
    pub fn parse(text: &str) -> Result<Self> {
        let root: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| input(format!("not valid TOML: {e}")))?;
        if let Some(key) = root.keys().find(|k| !SECTIONS.contains(&k.as_str())) {
            return Err(input(format!(
                "[{key}] is not a known section; allowed: {}",
                SECTIONS.join(", ")
            )));
        }
        let sun = parse_sun(&root)?;
        let (surface, ior) = parse_surface(&root)?;
        let (water, phase) = parse_water(&root)?;
        let floor = parse_floor(&root, &surface)?;
        let camera = parse_camera(&root, &surface, &floor)?;
        let render = parse_render(&root)?;
        Ok(Self {
            sun,
            surface,
            ior,
            water,
            phase,
            floor,
            camera,
            render,
        })
    }
}

fn parse_sun(root: &toml::Table) -> Result<Sun> {
    let mut s = Section::required(root, "sun")?;
    let direction = vec3(s.vector("direction", Some([0.0, 0.0, 1.0]), Range::FINITE)?);
    if !(direction.z > 0.0) {
        return Err(input(format!(
            "sun.direction = {:?} is out of range; allowed: a vector with z > 0 (the sun above the horizon)",
            direction.to_array()
        )));
    }
    let irradiance = s.number("irradiance", Some(1000.0), Range::EMISSION)?;
    let radius = s.number("angular_radius_deg", Some(0.27), Range::closed(0.0, 10.0))?;
    s.finish()?;
    Ok(Sun::new(
        direction,
        irradiance as f32,
        (radius as f32).to_radians(),
    ))
}

fn parse_surface(root: &toml::Table) -> Result<(Surface, f32)> {
    let mut s = Section::required(root, "surface")?;
    let z = s.number("z", Some(0.0), Range::FINITE)? as f32;
    let ior = s.number("ior", Some(1.33), Range::closed(1.0, 3.0))? as f32;
    let kind = s.choice("kind", SurfaceKind::Flat, SurfaceKind::ALL, "surface kind")?;
    // The phases a wave leaves out come from `surface.seed`.
    let mut phases = SplitMix64::new(s.integer("seed", 1, 0, i64::MAX)? as u64);
    let waves_value = s.get("waves");
    s.finish()?;
    let items: &[toml::Value] = match waves_value {
        None => &[],
        Some(toml::Value::Array(items)) => items,
        Some(v) => {
            return Err(input(format!(
                "surface.waves = {v} is not a list of tables; allowed: [[surface.waves]] sections"
            )));
        }
    };
    if kind == SurfaceKind::Flat {
        if !items.is_empty() {
            return Err(input(
                "surface.waves: kind = \"flat\" has no waves; allowed: kind = \"sine\" or \"gerstner\" with waves, or no [[surface.waves]]".into(),
            ));
        }
        return Ok((Surface::flat(z), ior));
    }
    let mut waves = Vec::new();
    for (i, item) in items.iter().enumerate() {
        let toml::Value::Table(t) = item else {
            return Err(input(format!(
                "surface.waves[{i}] = {item} is not a table; allowed: a [[surface.waves]] section"
            )));
        };
        let mut w = Section::of(t, format!("surface.waves[{i}]"));
        let amplitude = w.number("amplitude", None, Range::NON_NEGATIVE)?;
        let wavelength = w.number("wavelength", None, Range::POSITIVE)?;
        let direction = w
            .number("direction_deg", Some(0.0), Range::FINITE)?
            .to_radians();
        let random = (phases.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 360.0;
        let phase = w
            .number("phase_deg", Some(random), Range::FINITE)?
            .to_radians();
        w.finish()?;
        waves.push(Wave {
            amplitude: amplitude as f32,
            k: (std::f64::consts::TAU / wavelength) as f32,
            direction: Vec2::new(direction.cos() as f32, direction.sin() as f32),
            phase: phase as f32,
        });
    }
    let kind = if kind == SurfaceKind::Sine {
        WaveKind::Sine
    } else {
        WaveKind::Gerstner
    };
    let surface = Surface::new(z, kind, waves).map_err(|e| {
        input(format!(
            "surface.waves: the amplitudes fold the Gerstner surface (sum of amplitude * 2 pi / wavelength = {}); allowed: a sum below 1",
            e.steepness
        ))
    })?;
    Ok((surface, ior))
}

fn parse_water(root: &toml::Table) -> Result<(Water, PhaseSpec)> {
    let mut w = Section::required(root, "water")?;
    let sigma_s = vec3(w.rgb("sigma_s", None, Range::NON_NEGATIVE)?);
    let sigma_a = vec3(w.rgb("sigma_a", Some([0.0; 3]), Range::NON_NEGATIVE)?);
    let phase_text = w.string("phase", "iso", "a phase spec such as iso or ff:0.0183,1.1")?;
    let phase = PhaseSpec::parse(&phase_text).map_err(|e| e.context("water.phase"))?;
    w.finish()?;
    Ok((Water::new(sigma_s, sigma_a), phase))
}

fn parse_floor(root: &toml::Table, surface: &Surface) -> Result<Floor> {
    let mut f = Section::required(root, "floor")?;
    let trough = surface.trough() as f64;
    let z = f.number("z", Some(-4.0), Range::open(f64::NEG_INFINITY, trough))? as f32;
    let pattern = f.choice(
        "pattern",
        FloorPattern::Sand,
        FloorPattern::ALL,
        "floor pattern",
    )?;
    let floor = Floor {
        z,
        pattern,
        size: f.number("size", Some(0.5), Range::POSITIVE)? as f32,
        albedo_a: vec3(f.rgb("albedo_a", Some([0.75, 0.68, 0.5]), UNIT)?),
        albedo_b: vec3(f.rgb("albedo_b", Some([0.55, 0.48, 0.34]), UNIT)?),
    };
    f.finish()?;
    Ok(floor)
}

fn parse_camera(root: &toml::Table, surface: &Surface, floor: &Floor) -> Result<CameraSpec> {
    let mut c = Section::required(root, "camera")?;
    let position = vec3(c.vector("position", None, Range::FINITE)?);
    let (lo, hi) = (floor.z as f64, surface.trough() as f64);
    if !(position.z as f64 > lo && (position.z as f64) < hi) {
        return Err(RenderError::range(
            "camera.position[2]",
            position.z,
            format!(
                "(floor.z, surface.z - sum of wave amplitudes) = ({lo}, {hi}): in the water, below every trough"
            ),
        ));
    }
    let look_at = vec3(c.vector("look_at", Some([0.0, 0.0, floor.z as f64]), Range::FINITE)?);
    let up = vec3(c.vector("up", Some([0.0, 0.0, 1.0]), Range::FINITE)?);
    let fov = c.number("fov", Some(60.0), Range::open(0.0, 180.0))?;
    let width = c.integer("width", 480, 1, 16384)? as u32;
    let height = c.integer("height", 360, 1, 16384)? as u32;
    c.finish()?;
    let view = look_at - position;
    if !(view.length() > 0.0) {
        return Err(input(format!(
            "camera.look_at = {:?} equals camera.position; allowed: any other point",
            look_at.to_array()
        )));
    }
    if !(view.cross(up).length() > 1e-6 * view.length() * up.length()) {
        return Err(input(format!(
            "camera.up = {:?} is parallel to the view direction; allowed: any direction not parallel to look_at - position",
            up.to_array()
        )));
    }
    Ok(CameraSpec {
        position,
        look_at,
        up,
        fov: (fov as f32).to_radians(),
        width,
        height,
    })
}

fn parse_render(root: &toml::Table) -> Result<UnderwaterSettings> {
    let mut r = Section::required(root, "render")?;
    let default = &UNDERWATER_TERMS[..3];
    let listed = r.choices("terms", default, &UNDERWATER_TERMS, "term")?;
    let terms = UNDERWATER_TERMS.map(|t| listed.contains(&t));
    let technique = r.choice(
        "technique",
        Choice::Auto,
        &UNDERWATER_TECHNIQUES,
        "technique of the underwater scene",
    )?;
    let shafts = r.choice(
        "shafts",
        ShaftSampling::Mis,
        ShaftSampling::ALL,
        "shaft sampling",
    )?;
    let shafts_once_more = match r.choice(
        "shafts_once_more",
        Choice::LobeMis,
        &SHAFT_TECHNIQUES,
        "technique",
    )? {
        Choice::Omnee => LobeMethod::Omnee,
        _ => LobeMethod::LobeMis,
    };
    let settings = UnderwaterSettings {
        spp: r.integer("spp", 16, 1, 1 << 24)? as u32,
        seed: r.integer("seed", 1, 0, i64::MAX)? as u64,
        terms,
        technique,
        theta_max: r.number(
            "theta_max",
            Some(std::f64::consts::PI),
            Range::open_closed(0.0, std::f64::consts::PI),
        )?,
        mis_rate: r.number("mis_rate", Some(0.05), Range::closed(0.0, 1.0))?,
        mis_theta_min: r.number(
            "mis_theta_min",
            Some(0.75 * std::f64::consts::PI),
            Range::closed(0.0, std::f64::consts::PI),
        )?,
        shafts,
        shafts_once_more,
        once_more_samples: r.integer("once_more_samples", 4, 1, 1024)? as u32,
        shaft_samples: r.integer("shaft_samples", 16, 1, 1024)? as u32,
        margin: r.number("margin", Some(1.0), Range::closed(0.0, 1000.0))?,
        max_distance: r.number("max_distance", Some(30.0), Range::open_closed(0.0, 10000.0))?,
        camera_share: r.number("camera_share", Some(0.65), Range::closed(0.0, 1.0))?,
        eye_share: r.number("eye_share", Some(0.2), Range::closed(0.0, 1.0))?,
        eye_radius: r.number("eye_radius", Some(2.0), Range::POSITIVE)?,
        exposure: match r.get("exposure") {
            None => None,
            Some(toml::Value::String(s)) if s == "auto" => None,
            Some(_) => Some(r.number("exposure", None, Range::open(-64.0, 64.0))?),
        },
    };
    r.finish()?;
    let rest = 1.0 - settings.camera_share - settings.eye_share;
    if !(rest > 0.0) {
        return Err(RenderError::range(
            "render.eye_share",
            settings.eye_share,
            format!(
                "[0, 1 - render.camera_share) = [0, {}): some paths must start from the density that covers the whole surface",
                1.0 - settings.camera_share
            ),
        ));
    }
    Ok(settings)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field the parser reads, by section.
    const FIELDS: [(&str, &[&str]); 7] = [
        ("sun", &["direction", "irradiance", "angular_radius_deg"]),
        ("surface", &["z", "ior", "kind", "seed"]),
        (
            "surface.waves",
            &["amplitude", "wavelength", "direction_deg", "phase_deg"],
        ),
        ("water", &["sigma_s", "sigma_a", "phase"]),
        ("floor", &["z", "pattern", "size", "albedo_a", "albedo_b"]),
        (
            "camera",
            &["position", "look_at", "up", "fov", "width", "height"],
        ),
        (
            "render",
            &[
                "spp",
                "seed",
                "terms",
                "technique",
                "theta_max",
                "mis_rate",
                "mis_theta_min",
                "shafts",
                "shafts_once_more",
                "once_more_samples",
                "shaft_samples",
                "margin",
                "max_distance",
                "camera_share",
                "eye_share",
                "eye_radius",
                "exposure",
            ],
        ),
    ];

    #[test]
    fn the_builtin_scene_documents_every_field_with_default_and_range() {
        for (section, keys) in FIELDS {
            for key in keys {
                // The field's line and the comment lines continuing it.
                let lines: Vec<&str> = UNDERWATER_SCENE.lines().collect();
                let at = lines
                    .iter()
                    .position(|l| l.trim_start_matches("# ").starts_with(&format!("{key} =")))
                    .unwrap_or_else(|| panic!("{section}.{key} is not in the built-in scene"));
                let line =
                    std::iter::once(lines[at])
                        .chain(lines[at + 1..].iter().copied().take_while(|l| {
                            l.starts_with("    ") && l.trim_start().starts_with('#')
                        }))
                        .collect::<Vec<_>>()
                        .join(" ");
                assert!(
                    line.contains("default") || line.contains("required"),
                    "{section}.{key}: {line}"
                );
            }
        }
        // And the parser knows no other field: an unknown one is refused
        // with the list of the known ones.
        let text = UNDERWATER_SCENE.replacen("[sun]\n", "[sun]\nwobble = 1\n", 1);
        let e = UnderwaterScene::parse(&text).unwrap_err().to_string();
        assert!(
            e.contains("sun.wobble") && e.contains("angular_radius_deg, direction, irradiance"),
            "{e}"
        );
    }

    #[test]
    fn the_builtin_scene_parses_with_its_documented_values() {
        let s = UnderwaterScene::builtin();
        assert_eq!(s.ior, 1.33);
        assert!(!s.surface.is_flat());
        assert_eq!(s.floor.z, -4.0);
        assert_eq!(s.render.terms, [true, true, true, false]);
        assert_eq!(s.render.technique, Choice::Mis);
        assert!((s.sun.angular_radius - 0.27f32.to_radians()).abs() < 1e-9);
    }
}

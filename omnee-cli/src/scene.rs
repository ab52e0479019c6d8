//! Scene files: TOML with every parameter of the slab scene, validated field
//! by field. Every error names the field (`section.key`), its value and the
//! allowed range. The default scene is `scenes/default.toml`, embedded in the
//! binary, and documents every field.

use crate::error::{CliError, Result};
use crate::phase::PhaseSpec;
use std::collections::BTreeSet;
use std::fmt;

/// The default scene, as shipped in `omnee-cli/scenes/default.toml`.
pub const DEFAULT_SCENE: &str = include_str!("../scenes/default.toml");

/// An interval of allowed values, printed in interval notation.
#[derive(Clone, Copy, Debug)]
pub struct Range {
    lo: f64,
    hi: f64,
    lo_open: bool,
    hi_open: bool,
}

impl Range {
    /// `[lo, hi]`.
    pub const fn closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: false,
            hi_open: false,
        }
    }
    /// `(lo, hi)`.
    pub const fn open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: true,
        }
    }
    /// `(lo, hi]`.
    pub const fn open_closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: false,
        }
    }
    /// Any finite number.
    pub const FINITE: Self = Self::open(f64::NEG_INFINITY, f64::INFINITY);
    /// `[0, inf)`.
    pub const NON_NEGATIVE: Self = Self::closed(0.0, f64::INFINITY);
    /// `(0, inf)`.
    pub const POSITIVE: Self = Self::open(0.0, f64::INFINITY);

    /// Whether `x` is finite and inside.
    pub fn contains(&self, x: f64) -> bool {
        x.is_finite()
            && (if self.lo_open {
                x > self.lo
            } else {
                x >= self.lo
            })
            && (if self.hi_open {
                x < self.hi
            } else {
                x <= self.hi
            })
    }

    /// Checks `x`, naming `field` on failure.
    pub fn check(&self, field: &str, x: f64) -> Result<f64> {
        if self.contains(x) {
            Ok(x)
        } else {
            Err(CliError::range(field, x, self))
        }
    }
}

impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.lo == f64::NEG_INFINITY && self.hi == f64::INFINITY {
            return f.write_str("any finite number");
        }
        let end = |x: f64| {
            if x == f64::INFINITY {
                "inf".to_string()
            } else if x == f64::NEG_INFINITY {
                "-inf".to_string()
            } else {
                format!("{x}")
            }
        };
        write!(
            f,
            "{}{}, {}{}",
            if self.lo_open || self.lo.is_infinite() {
                '('
            } else {
                '['
            },
            end(self.lo),
            end(self.hi),
            if self.hi_open || self.hi.is_infinite() {
                ')'
            } else {
                ']'
            }
        )
    }
}

/// The scattering medium: a homogeneous slab `z_min ≤ z ≤ z_max`.
#[derive(Clone, Debug)]
pub struct Medium {
    /// Scattering coefficient σs (1/m).
    pub sigma_s: f64,
    /// Absorption coefficient σa (1/m).
    pub sigma_a: f64,
    /// The phase function.
    pub phase: PhaseSpec,
    /// The slab's lower plane.
    pub z_min: f64,
    /// The slab's upper plane.
    pub z_max: f64,
}

impl Medium {
    /// σt = σs + σa.
    pub fn sigma_t(&self) -> f64 {
        self.sigma_s + self.sigma_a
    }
}

/// A diffuse floor plane `z = const` with a checker albedo.
#[derive(Clone, Debug)]
pub struct Floor {
    /// Height of the plane.
    pub z: f64,
    /// Edge length of one checker square (m).
    pub checker_size: f64,
    /// RGB albedo of the squares with even `floor(x/size) + floor(y/size)`.
    pub albedo_a: [f64; 3],
    /// RGB albedo of the other squares.
    pub albedo_b: [f64; 3],
}

/// A spherical area light of uniform radiance, or a point light.
#[derive(Clone, Debug)]
pub struct Light {
    /// Centre of the sphere (m).
    pub center: [f64; 3],
    /// Radius (m); 0 for a point light.
    pub radius: f64,
    /// Radiance of the sphere's surface (W/(m²·sr)); 0 for a point light.
    pub radiance: f64,
    /// Radiant intensity (W/sr): given for a point light, `radiance·π r²`
    /// for a sphere (its intensity in every direction).
    pub intensity: f64,
}

/// The occluder's pattern of openings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// No openings.
    Solid,
    /// Slits parallel to the y axis, repeating along x.
    Bars,
    /// Round holes on a square lattice.
    Holes,
}

/// An opaque horizontal plate with openings.
#[derive(Clone, Debug)]
pub struct Occluder {
    /// Centre of the plate (its z is the plate's height).
    pub center: [f64; 3],
    /// Extent along x and y (m).
    pub size: [f64; 2],
    /// The openings.
    pub pattern: Pattern,
    /// The pattern's period (m).
    pub period: f64,
    /// Open fraction: slit width / period, or hole diameter / period.
    pub opening: f64,
    /// RGB albedo of the plate (diffuse, both sides).
    pub albedo: [f64; 3],
}

/// A pinhole camera.
#[derive(Clone, Debug)]
pub struct Camera {
    /// Eye position.
    pub position: [f64; 3],
    /// The point the camera looks at.
    pub look_at: [f64; 3],
    /// The up direction (not parallel to the view direction).
    pub up: [f64; 3],
    /// Vertical field of view in degrees.
    pub fov_deg: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

/// Render settings stored in the scene (command-line options override them).
#[derive(Clone, Debug)]
pub struct RenderSettings {
    /// Samples per pixel.
    pub spp: u32,
    /// Random seed.
    pub seed: u64,
    /// Transport terms to evaluate.
    pub terms: Vec<String>,
    /// Technique for the once-more term.
    pub technique: String,
    /// The once-more integrand's restriction θ < θmax (radians).
    pub theta_max: f64,
    /// Russian roulette threshold as a fraction of the reference radiance.
    pub russian_roulette: f64,
    /// Exposure in stops for the PNG; `None` picks it from the image.
    pub exposure: Option<f64>,
}

/// A whole scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The slab medium.
    pub medium: Medium,
    /// The floor.
    pub floor: Floor,
    /// The light.
    pub light: Light,
    /// The occluder, if any.
    pub occluder: Option<Occluder>,
    /// The camera.
    pub camera: Camera,
    /// Render settings.
    pub render: RenderSettings,
}

/// A section that `Section::new(.., required = true)` always returns.
fn some(s: Option<Section<'_>>) -> Section<'_> {
    s.expect("required sections always exist")
}

/// One table of the TOML document, with the keys read so far (the rest are
/// reported as unknown).
struct Section<'a> {
    name: &'static str,
    table: Option<&'a toml::Table>,
    used: BTreeSet<&'static str>,
}

impl<'a> Section<'a> {
    fn new(root: &'a toml::Table, name: &'static str, required: bool) -> Result<Option<Self>> {
        match root.get(name) {
            None if required => Ok(Some(Self {
                name,
                table: None,
                used: BTreeSet::new(),
            })),
            None => Ok(None),
            Some(toml::Value::Table(t)) => Ok(Some(Self {
                name,
                table: Some(t),
                used: BTreeSet::new(),
            })),
            Some(v) => Err(CliError::Input(format!(
                "{name} = {v} is not a table; allowed: a [{name}] section"
            ))),
        }
    }

    fn field(&self, key: &str) -> String {
        format!("{}.{key}", self.name)
    }

    fn get(&mut self, key: &'static str) -> Option<&'a toml::Value> {
        self.used.insert(key);
        self.table.and_then(|t| t.get(key))
    }

    fn number(&mut self, key: &'static str, default: Option<f64>, range: Range) -> Result<f64> {
        let field = self.field(key);
        let x = match self.get(key) {
            None => default
                .ok_or_else(|| CliError::Input(format!("{field} is missing; allowed: {range}")))?,
            Some(toml::Value::Float(x)) => *x,
            Some(toml::Value::Integer(i)) => *i as f64,
            Some(v) => {
                return Err(CliError::Input(format!(
                    "{field} = {v} is not a number; allowed: {range}"
                )));
            }
        };
        range.check(&field, x)
    }

    fn integer(&mut self, key: &'static str, default: i64, lo: i64, hi: i64) -> Result<i64> {
        let field = self.field(key);
        match self.get(key) {
            None => Ok(default),
            Some(toml::Value::Integer(i)) if (lo..=hi).contains(i) => Ok(*i),
            Some(v) => Err(CliError::Input(format!(
                "{field} = {v} is out of range; allowed: an integer in [{lo}, {hi}]"
            ))),
        }
    }

    fn vector<const N: usize>(
        &mut self,
        key: &'static str,
        default: Option<[f64; N]>,
        range: Range,
    ) -> Result<[f64; N]> {
        let field = self.field(key);
        let allowed = format!("an array of {N} numbers, each {range}");
        let v = match self.get(key) {
            None => {
                return default.ok_or_else(|| {
                    CliError::Input(format!("{field} is missing; allowed: {allowed}"))
                });
            }
            Some(v) => v,
        };
        let bad = || CliError::Input(format!("{field} = {v} is out of range; allowed: {allowed}"));
        let toml::Value::Array(items) = v else {
            return Err(bad());
        };
        if items.len() != N {
            return Err(bad());
        }
        let mut out = [0.0; N];
        for (slot, item) in out.iter_mut().zip(items) {
            *slot = match item {
                toml::Value::Float(x) => *x,
                toml::Value::Integer(i) => *i as f64,
                _ => return Err(bad()),
            };
            if !range.contains(*slot) {
                return Err(bad());
            }
        }
        Ok(out)
    }

    fn string(&mut self, key: &'static str, default: &str, allowed: &str) -> Result<String> {
        let field = self.field(key);
        match self.get(key) {
            None => Ok(default.to_string()),
            Some(toml::Value::String(s)) => Ok(s.clone()),
            Some(v) => Err(CliError::Input(format!(
                "{field} = {v} is not a string; allowed: {allowed}"
            ))),
        }
    }

    fn strings(
        &mut self,
        key: &'static str,
        default: &[&str],
        allowed: &str,
    ) -> Result<Vec<String>> {
        let field = self.field(key);
        match self.get(key) {
            None => Ok(default.iter().map(|s| s.to_string()).collect()),
            Some(toml::Value::Array(items)) => items
                .iter()
                .map(|i| match i {
                    toml::Value::String(s) => Ok(s.clone()),
                    _ => Err(CliError::Input(format!(
                        "{field} = {} is not a list of strings; allowed: {allowed}",
                        toml::Value::Array(items.clone())
                    ))),
                })
                .collect(),
            Some(v) => Err(CliError::Input(format!(
                "{field} = {v} is not a list of strings; allowed: {allowed}"
            ))),
        }
    }

    /// Fails on the first key that was never read.
    fn finish(self) -> Result<()> {
        if let Some(t) = self.table {
            for (k, v) in t {
                if !self.used.contains(k.as_str()) {
                    return Err(CliError::Input(format!(
                        "{}.{k} = {v} is not a known field; allowed: {}",
                        self.name,
                        self.used.iter().copied().collect::<Vec<_>>().join(", ")
                    )));
                }
            }
        }
        Ok(())
    }
}

const UNIT: Range = Range::closed(0.0, 1.0);
/// The allowed transport terms.
pub const TERMS: [&str; 3] = ["direct", "once-more", "view"];
/// The allowed once-more techniques.
pub const TECHNIQUES: [&str; 5] = ["omnee", "equiangular", "distance", "mis", "auto"];

impl Scene {
    /// The embedded default scene.
    pub fn default_scene() -> Self {
        Self::parse(DEFAULT_SCENE).expect("the embedded default scene is valid")
    }

    /// Parses and validates a scene from TOML text.
    pub fn parse(text: &str) -> Result<Self> {
        let root: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| CliError::Input(format!("not valid TOML: {e}")))?;
        for key in root.keys() {
            if !["medium", "floor", "light", "occluder", "camera", "render"].contains(&key.as_str())
            {
                return Err(CliError::Input(format!(
                    "[{key}] is not a known section; allowed: medium, floor, light, occluder, camera, render"
                )));
            }
        }

        let mut m = some(Section::new(&root, "medium", true)?);
        let sigma_s = m.number("sigma_s", None, Range::NON_NEGATIVE)?;
        let sigma_a = m.number("sigma_a", Some(0.0), Range::NON_NEGATIVE)?;
        let phase_text = m.string("phase", "iso", "a phase spec such as iso or hg:0.9")?;
        let phase = PhaseSpec::parse(&phase_text).map_err(|e| e.context("medium.phase"))?;
        let z_min = m.number("z_min", Some(0.0), Range::FINITE)?;
        let z_max = m.number("z_max", Some(1.0), Range::open(z_min, f64::INFINITY))?;
        m.finish()?;
        let medium = Medium {
            sigma_s,
            sigma_a,
            phase,
            z_min,
            z_max,
        };

        let mut f = some(Section::new(&root, "floor", true)?);
        let floor = Floor {
            z: f.number("z", Some(0.0), Range::FINITE)?,
            checker_size: f.number("checker_size", Some(0.25), Range::POSITIVE)?,
            albedo_a: f.vector("albedo_a", Some([0.8; 3]), UNIT)?,
            albedo_b: f.vector("albedo_b", Some([0.2; 3]), UNIT)?,
        };
        f.finish()?;

        let mut l = some(Section::new(&root, "light", true)?);
        let center = l.vector("center", None, Range::FINITE)?;
        let radius = l.number("radius", Some(0.0), Range::NON_NEGATIVE)?;
        let light = if radius > 0.0 {
            let radiance = l.number("radiance", None, Range::NON_NEGATIVE)?;
            if l.table.and_then(|t| t.get("intensity")).is_some() {
                return Err(CliError::Input(
                    "light.intensity is only for a point light (radius = 0); allowed: radiance for a sphere".into(),
                ));
            }
            Light {
                center,
                radius,
                radiance,
                intensity: radiance * std::f64::consts::PI * radius * radius,
            }
        } else {
            if l.table.and_then(|t| t.get("radiance")).is_some() {
                return Err(CliError::Input(
                    "light.radiance needs a sphere (radius > 0); allowed: intensity for a point light".into(),
                ));
            }
            Light {
                center,
                radius,
                radiance: 0.0,
                intensity: l.number("intensity", None, Range::NON_NEGATIVE)?,
            }
        };
        l.used.insert("radiance");
        l.used.insert("intensity");
        l.finish()?;
        if center[2] - radius <= floor.z {
            return Err(CliError::range(
                "light.center[2]",
                center[2],
                format!(
                    "(floor.z + light.radius, inf) = ({}, inf)",
                    floor.z + radius
                ),
            ));
        }

        let occluder = match Section::new(&root, "occluder", false)? {
            None => None,
            Some(mut o) => {
                let center = o.vector("center", None, Range::FINITE)?;
                let size = o.vector("size", None, Range::POSITIVE)?;
                let pattern = match o
                    .string("pattern", "bars", "solid, bars or holes")?
                    .as_str()
                {
                    "solid" => Pattern::Solid,
                    "bars" => Pattern::Bars,
                    "holes" => Pattern::Holes,
                    other => {
                        return Err(CliError::Input(format!(
                            "occluder.pattern = \"{other}\" is not a pattern; allowed: solid, bars or holes"
                        )));
                    }
                };
                let period = o.number("period", Some(0.1), Range::POSITIVE)?;
                let opening = o.number("opening", Some(0.5), Range::open(0.0, 1.0))?;
                let albedo = o.vector("albedo", Some([0.0; 3]), UNIT)?;
                o.finish()?;
                if center[2] <= floor.z {
                    return Err(CliError::range(
                        "occluder.center[2]",
                        center[2],
                        format!("(floor.z, inf) = ({}, inf)", floor.z),
                    ));
                }
                let dz = (center[2] - light.center[2]).abs();
                if dz <= light.radius {
                    return Err(CliError::range(
                        "occluder.center[2]",
                        center[2],
                        format!(
                            "|z - light.center[2]| > light.radius = {} (the plate may not cut the light)",
                            light.radius
                        ),
                    ));
                }
                Some(Occluder {
                    center,
                    size,
                    pattern,
                    period,
                    opening,
                    albedo,
                })
            }
        };

        let mut c = some(Section::new(&root, "camera", true)?);
        let camera = Camera {
            position: c.vector("position", None, Range::FINITE)?,
            look_at: c.vector("look_at", Some([0.0; 3]), Range::FINITE)?,
            up: c.vector("up", Some([0.0, 1.0, 0.0]), Range::FINITE)?,
            fov_deg: c.number("fov", Some(40.0), Range::open(0.0, 180.0))?,
            width: c.integer("width", 480, 1, 16384)? as u32,
            height: c.integer("height", 360, 1, 16384)? as u32,
        };
        c.finish()?;
        let view = sub(camera.look_at, camera.position);
        if norm(view) == 0.0 {
            return Err(CliError::Input(format!(
                "camera.look_at = {:?} equals camera.position; allowed: any other point",
                camera.look_at
            )));
        }
        if norm(cross(view, camera.up)) <= 1e-9 * norm(view) * norm(camera.up) {
            return Err(CliError::Input(format!(
                "camera.up = {:?} is parallel to the view direction; allowed: any direction not parallel to look_at - position",
                camera.up
            )));
        }
        if light.radius > 0.0 && norm(sub(camera.position, light.center)) <= light.radius {
            return Err(CliError::Input(format!(
                "camera.position = {:?} is inside the light; allowed: outside the sphere of radius {} about {:?}",
                camera.position, light.radius, light.center
            )));
        }

        let render = match Section::new(&root, "render", false)? {
            None => RenderSettings::defaults(),
            Some(mut r) => {
                let d = RenderSettings::defaults();
                let terms = r.strings("terms", &TERMS, "a list of direct, once-more, view")?;
                let settings = RenderSettings {
                    spp: r.integer("spp", d.spp as i64, 1, 1 << 24)? as u32,
                    seed: r.integer("seed", d.seed as i64, 0, i64::MAX)? as u64,
                    terms,
                    technique: r.string(
                        "technique",
                        &d.technique,
                        "omnee, equiangular, distance, mis or auto",
                    )?,
                    theta_max: r.number(
                        "theta_max",
                        Some(d.theta_max),
                        Range::open_closed(0.0, std::f64::consts::PI),
                    )?,
                    russian_roulette: r.number(
                        "russian_roulette",
                        Some(d.russian_roulette),
                        UNIT,
                    )?,
                    exposure: match r.get("exposure") {
                        None => None,
                        Some(toml::Value::String(s)) if s == "auto" => None,
                        Some(_) => Some(r.number("exposure", None, Range::open(-64.0, 64.0))?),
                    },
                };
                r.finish()?;
                check_terms("render.terms", &settings.terms)?;
                check_technique("render.technique", &settings.technique)?;
                settings
            }
        };

        Ok(Scene {
            medium,
            floor,
            light,
            occluder,
            camera,
            render,
        })
    }

    /// Reads and parses a scene file; errors are prefixed with the path.
    pub fn load(path: &std::path::Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            CliError::Input(format!("--scene = {}: cannot read: {e}", path.display()))
        })?;
        Self::parse(&text).map_err(|e| e.context(&path.display().to_string()))
    }
}

impl RenderSettings {
    /// The settings when the scene has no `[render]` section.
    pub fn defaults() -> Self {
        Self {
            spp: 16,
            seed: 1,
            terms: TERMS.iter().map(|s| s.to_string()).collect(),
            technique: "auto".into(),
            theta_max: std::f64::consts::PI,
            russian_roulette: 1e-3,
            exposure: None,
        }
    }
}

/// Checks a list of transport term names.
pub fn check_terms(field: &str, terms: &[String]) -> Result<()> {
    for t in terms {
        if !TERMS.contains(&t.as_str()) {
            return Err(CliError::Input(format!(
                "{field} = \"{t}\" is not a term; allowed: direct, once-more, view"
            )));
        }
    }
    if terms.is_empty() {
        return Err(CliError::Input(format!(
            "{field} is empty; allowed: one or more of direct, once-more, view"
        )));
    }
    Ok(())
}

/// Checks a technique name.
pub fn check_technique(field: &str, t: &str) -> Result<()> {
    if TECHNIQUES.contains(&t) {
        Ok(())
    } else {
        Err(CliError::Input(format!(
            "{field} = \"{t}\" is not a technique; allowed: omnee, equiangular, distance, mis, auto"
        )))
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_scene_parses() {
        let s = Scene::default_scene();
        assert_eq!(s.medium.sigma_s, 0.5);
        assert_eq!(s.medium.sigma_a, 0.05);
        assert!(s.occluder.is_some());
    }

    #[test]
    fn errors_name_field_value_and_range() {
        let bad = DEFAULT_SCENE.replace("sigma_s = 0.5", "sigma_s = -2");
        let e = Scene::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("medium.sigma_s = -2"), "{e}");
        assert!(e.contains("[0, inf)"), "{e}");
        let bad = DEFAULT_SCENE.replace("sigma_s = 0.5", "sigma_s = 0.5\nsigma_x = 1");
        let e = Scene::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("medium.sigma_x"), "{e}");
    }

    #[test]
    fn range_display() {
        assert_eq!(Range::open_closed(0.0, 3.5).to_string(), "(0, 3.5]");
        assert_eq!(Range::NON_NEGATIVE.to_string(), "[0, inf)");
    }
}

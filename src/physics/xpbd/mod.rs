//! XPBD cloth two-way coupled with rigid boxes on a table: the cloth scenario's truth solver, in
//! the role of the release's Obi Cloth with PhysX boxes (`docs/data/cloth.md`).
//!
//! One solver moves both: every substep predicts cloth particles and boxes, projects the cloth's
//! stretch and bend constraints, the particles' contacts with the table, the boxes and each
//! other, and the boxes' contacts with the table and each other, all as XPBD position
//! constraints with their multipliers accumulated over the substep's iterations, then derives
//! velocities and removes the boxes' approaching normal velocities. A cloth particle pressing on a box moves
//! the box by the box's generalised inverse mass, so the coupling is two-way with no impulse
//! exchange between separate solvers. Why one solver rather than a rigid-body crate coupled
//! through impulses: a box pushed by a cloth and a box held by a cloth are the same constraint
//! here, which keeps a 99999-kg box immovable and a 2-kg plate free in the same pass.
//!
//! Units: metres, kilograms, seconds; `y` is up; the table's top is at `table_height`. Time
//! advances by updates of [`XpbdSettings::update_seconds`] (the release's 1/60 s). Input: the
//! settings, sheets ([`Sheet`]) and boxes ([`BoxBody`]). Output: poses after every update, the
//! contacts each update had ([`UpdateContacts`]), and [`XpbdError::NonFinite`] the moment
//! anything stops being finite.

mod box_edges;
mod contact;
pub mod rigid;
pub mod sheet;

#[cfg(test)]
mod tests;

use std::collections::BTreeSet;

pub use rigid::BoxBody;
pub use sheet::{Sheet, SheetProperties, SheetSpec};

use crate::physics::vector3::{self as v3, Vector};

/// One update of the release, seconds.
pub const UPDATE_SECONDS: f64 = 1.0 / 60.0;
/// Gravity, m/s² (Unity's default, along −y).
pub const GRAVITY: Vector = [0.0, -9.81, 0.0];

/// Errors of the cloth solver.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum XpbdError {
    /// A setting is out of its range.
    #[error("XPBD solver setting `{name}` is {value}; {expected}")]
    InvalidSetting {
        /// The setting.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// A box cannot be simulated.
    #[error("box {index}: {reason}")]
    InvalidBox {
        /// Its index in the world.
        index: usize,
        /// Why.
        reason: String,
    },
    /// A position or velocity stopped being finite.
    #[error("XPBD solver: {body} is not finite at update {update}")]
    NonFinite {
        /// The update it happened in (counted from the world's start).
        update: usize,
        /// Which body (`sheet 0`, `box 2`).
        body: String,
    },
}

/// Solver settings.
#[derive(Debug, Clone, PartialEq)]
pub struct XpbdSettings {
    /// Length of an update, seconds.
    pub update_seconds: f64,
    /// Substeps per update.
    pub substeps: usize,
    /// Constraint iterations per substep.
    pub iterations: usize,
    /// Gravity, m/s² (a tilted gravity stands for an inclined table in the tests).
    pub gravity: Vector,
    /// Velocity damping of cloth particles, 1/s (the release's solver: 0.01).
    pub damping: f64,
    /// Friction coefficient between boxes and between a box and the table (PhysX's default
    /// material: 0.6 static and dynamic).
    pub rigid_friction: f64,
    /// Height of the table's top, metres.
    pub table_height: f64,
    /// Whether cloth particles collide with the same cloth's other particles.
    pub self_collision: bool,
    /// Whether the boxes' edges collide with the cloth's triangles (besides its particles), so
    /// that a box's edge cannot slip between two particles (`box_edges`).
    pub box_edges: bool,
    /// Cloth particle speeds are capped here, m/s: above anything the scene moves at (the
    /// handle: 3 m/s; a 3-metre fall: 7.7 m/s). A cloth snagged on a box while the handle pulls
    /// stores stretch its few iterations cannot remove, and when it comes free the constraint
    /// would fling particles at up to 80 m/s (measured); the cap keeps that from happening.
    pub max_speed: f64,
}

impl Default for XpbdSettings {
    fn default() -> Self {
        XpbdSettings {
            update_seconds: UPDATE_SECONDS,
            substeps: 10,
            iterations: 2,
            gravity: GRAVITY,
            damping: 0.01,
            rigid_friction: 0.6,
            table_height: 0.0,
            self_collision: true,
            box_edges: true,
            max_speed: 15.0,
        }
    }
}

impl XpbdSettings {
    /// Checks every setting's range.
    pub fn validate(&self) -> Result<(), XpbdError> {
        let checks: [(&'static str, f64, bool, &'static str); 7] = [
            (
                "update_seconds",
                self.update_seconds,
                self.update_seconds > 0.0 && self.update_seconds <= 1.0,
                "expected a positive update of at most a second",
            ),
            (
                "substeps",
                self.substeps as f64,
                (1..=10_000).contains(&self.substeps),
                "expected 1 to 10000",
            ),
            (
                "iterations",
                self.iterations as f64,
                (1..=1000).contains(&self.iterations),
                "expected 1 to 1000",
            ),
            (
                "gravity",
                crate::physics::vector3::norm(self.gravity),
                self.gravity.iter().all(|g| g.is_finite()),
                "expected a finite vector",
            ),
            (
                "damping",
                self.damping,
                self.damping >= 0.0 && self.damping.is_finite(),
                "expected a finite value of at least 0",
            ),
            (
                "max_speed",
                self.max_speed,
                self.max_speed > 0.0,
                "expected a positive speed",
            ),
            (
                "rigid_friction",
                self.rigid_friction,
                self.rigid_friction >= 0.0 && self.rigid_friction.is_finite(),
                "expected a finite value of at least 0",
            ),
        ];
        for (name, value, valid, expected) in checks {
            if !valid {
                return Err(XpbdError::InvalidSetting {
                    name,
                    value,
                    expected,
                });
            }
        }
        Ok(())
    }
}

/// What touched what during one update (any substep).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct UpdateContacts {
    /// Boxes touching each other, `(lower index, higher index)`.
    pub box_pairs: BTreeSet<(usize, usize)>,
    /// A box touched by a cloth, `(sheet, box)`.
    pub sheet_boxes: BTreeSet<(usize, usize)>,
    /// Boxes standing on or touching the table.
    pub table_boxes: BTreeSet<usize>,
}

/// A sheet's self-contact candidates, kept while no two particles can have closed the margin
/// they were found with.
#[derive(Debug, Clone, Default)]
struct SelfContacts {
    /// Candidate pairs (closer than two radii plus the margin when found).
    pairs: Vec<(usize, usize)>,
    /// How much closer any two particles may still have come, metres; below 0 the pairs are
    /// found again.
    budget: f64,
}

/// The simulated world: cloths and boxes on a table.
#[derive(Debug, Clone)]
pub struct World {
    settings: XpbdSettings,
    sheets: Vec<Sheet>,
    boxes: Vec<BoxBody>,
    samples: Vec<Vec<Vector>>,
    self_contacts: Vec<SelfContacts>,
    updates: usize,
}

impl World {
    /// An empty world.
    pub fn new(settings: XpbdSettings) -> Result<World, XpbdError> {
        settings.validate()?;
        Ok(World {
            settings,
            sheets: Vec::new(),
            boxes: Vec::new(),
            samples: Vec::new(),
            self_contacts: Vec::new(),
            updates: 0,
        })
    }

    /// Adds a cloth; returns its index.
    pub fn add_sheet(&mut self, sheet: Sheet) -> usize {
        self.sheets.push(sheet);
        self.self_contacts.push(SelfContacts::default());
        self.sheets.len() - 1
    }

    /// Adds a box; returns its index. Mass and extents must be positive and finite.
    pub fn add_box(&mut self, body: BoxBody) -> Result<usize, XpbdError> {
        let index = self.boxes.len();
        if !(body.mass > 0.0 && body.mass.is_finite()) {
            return Err(XpbdError::InvalidBox {
                index,
                reason: format!("mass {} kg is not positive and finite", body.mass),
            });
        }
        if !body.half_extents.iter().all(|h| *h > 0.0 && h.is_finite()) || !body.is_finite() {
            return Err(XpbdError::InvalidBox {
                index,
                reason: format!(
                    "half extents {:?} m or its pose is not positive and finite",
                    body.half_extents
                ),
            });
        }
        self.samples.push(contact::box_samples(body.half_extents));
        self.boxes.push(body);
        Ok(index)
    }

    /// The settings.
    pub fn settings(&self) -> &XpbdSettings {
        &self.settings
    }

    /// The cloths.
    pub fn sheets(&self) -> &[Sheet] {
        &self.sheets
    }

    /// A cloth, to grip, drive or release it.
    pub fn sheet_mut(&mut self, index: usize) -> Option<&mut Sheet> {
        self.sheets.get_mut(index)
    }

    /// The boxes.
    pub fn boxes(&self) -> &[BoxBody] {
        &self.boxes
    }

    /// The pairs of boxes (lower index first) whose surfaces are within `tolerance` metres of
    /// each other now (a sample point of one inside the other grown by `tolerance`): the steady
    /// reading of which boxes touch, where [`UpdateContacts::box_pairs`] lists the pairs a
    /// contact pushed apart, which flickers for a box resting on another.
    pub fn box_pairs_within(&self, tolerance: f64) -> BTreeSet<(usize, usize)> {
        contact::box_pairs_within(&self.boxes, &self.samples, tolerance)
    }

    /// Updates done so far.
    pub fn updates(&self) -> usize {
        self.updates
    }

    /// Substep length, seconds.
    pub fn substep_seconds(&self) -> f64 {
        self.settings.update_seconds / self.settings.substeps as f64
    }

    /// Advances one update; returns what touched what during it.
    pub fn step(&mut self) -> Result<UpdateContacts, XpbdError> {
        let mut contacts = UpdateContacts::default();
        for _ in 0..self.settings.substeps {
            self.substep(&mut contacts);
        }
        self.updates += 1;
        self.check_finite()?;
        Ok(contacts)
    }

    /// One substep, recording its contacts into `log`.
    fn substep(&mut self, log: &mut UpdateContacts) {
        let settings = &self.settings;
        let h = settings.update_seconds / settings.substeps as f64;
        for body in &mut self.boxes {
            body.predict(h, settings.gravity);
        }
        for sheet in &mut self.sheets {
            sheet.predict(h, settings.gravity, settings.damping);
        }
        let mut rigid =
            contact::find_rigid_contacts(&self.boxes, &self.samples, settings.table_height);
        if settings.self_collision {
            for (sheet, cache) in self.sheets.iter().zip(&mut self.self_contacts) {
                // Two particles close at most twice the fastest one's speed; the candidates
                // stay complete until that has used up the margin they were found with.
                let fastest = sheet
                    .velocities
                    .iter()
                    .map(|v| v3::norm(*v))
                    .fold(0.0, f64::max);
                cache.budget -= 2.0 * fastest * h;
                if cache.budget <= 0.0 {
                    let margin = 4.0 * sheet.particle_radius();
                    let reach = 2.0 * sheet.particle_radius() + margin;
                    cache.pairs = contact::find_self_contacts(sheet, reach);
                    cache.budget = margin - 2.0 * fastest * h;
                }
            }
        }
        let mut touched = vec![vec![false; self.boxes.len()]; self.sheets.len()];
        for _ in 0..settings.iterations {
            // Without self-collision the candidate lists stay empty.
            for ((sheet, candidates), touched) in self
                .sheets
                .iter_mut()
                .zip(&self.self_contacts)
                .zip(&mut touched)
            {
                sheet.project_stretch(h);
                sheet.project_bend();
                let friction = sheet.properties().friction;
                contact::project_particles_on_table(sheet, settings.table_height, friction);
                contact::project_particles_on_boxes(sheet, &mut self.boxes, friction, touched);
                if settings.box_edges {
                    box_edges::project_box_edges(sheet, &mut self.boxes, friction, touched);
                }
                contact::project_self_contacts(sheet, &candidates.pairs);
            }
            contact::project_rigid(&mut self.boxes, &mut rigid, settings.rigid_friction);
        }
        for body in &mut self.boxes {
            body.derive_velocities(h);
        }
        for sheet in &mut self.sheets {
            sheet.derive_velocities(h, settings.max_speed);
        }
        contact::rigid_velocities(&mut self.boxes, &rigid);
        for contact in rigid.contacts.iter().filter(|c| c.normal_multiplier > 0.0) {
            match contact.other {
                contact::Other::Table(_) => {
                    log.table_boxes.insert(contact.body);
                }
                contact::Other::Box(other, _) => {
                    let pair = (contact.body.min(other), contact.body.max(other));
                    log.box_pairs.insert(pair);
                }
            }
        }
        for (sheet, touched) in touched.iter().enumerate() {
            for (body, _) in touched.iter().enumerate().filter(|(_, t)| **t) {
                log.sheet_boxes.insert((sheet, body));
            }
        }
    }

    /// [`XpbdError::NonFinite`] naming the first body that is not finite.
    fn check_finite(&self) -> Result<(), XpbdError> {
        let bad_sheet = self.sheets.iter().position(|s| !s.is_finite());
        let bad_box = self.boxes.iter().position(|b| !b.is_finite());
        let body = match (bad_sheet, bad_box) {
            (Some(index), _) => format!("sheet {index}"),
            (None, Some(index)) => format!("box {index}"),
            (None, None) => return Ok(()),
        };
        Err(XpbdError::NonFinite {
            update: self.updates,
            body,
        })
    }
}

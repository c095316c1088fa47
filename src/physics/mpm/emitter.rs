//! Emitters of the MPM core: a line segment that releases rows of particles of one material at a
//! fixed speed while open (`start ≤ t < stop`) and until it has released its particle budget.
//! A new row is laid each time the previous one has moved one particle spacing, so the emitted
//! stream has the material's rest density. Input: time and substep. Output: new particles.

/// An emitter.
#[derive(Debug, Clone, PartialEq)]
pub struct Emitter {
    /// Material index of what it emits.
    pub material: usize,
    /// Centre of the emitting segment.
    pub center: [f64; 2],
    /// Unit direction of emission (perpendicular to the segment).
    pub direction: [f64; 2],
    /// Segment width.
    pub width: f64,
    /// Emission speed.
    pub speed: f64,
    /// Spacing of the particles it lays (their volume is `spacing²`).
    pub spacing: f64,
    /// Opening time, s.
    pub start: f64,
    /// Closing time, s.
    pub stop: f64,
    /// Most particles it releases.
    pub budget: usize,
    /// Particles released so far.
    pub(super) released: usize,
    /// Distance the last row has travelled since it was laid.
    pub(super) travelled: f64,
}

impl Emitter {
    /// An emitter that has released nothing yet.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        material: usize,
        center: [f64; 2],
        direction: [f64; 2],
        width: f64,
        speed: f64,
        spacing: f64,
        window: (f64, f64),
        budget: usize,
    ) -> Emitter {
        Emitter {
            material,
            center,
            direction,
            width,
            speed,
            spacing,
            start: window.0,
            stop: window.1,
            budget,
            released: 0,
            // The first row is laid at once.
            travelled: spacing,
        }
    }

    /// Particles released so far.
    pub fn released(&self) -> usize {
        self.released
    }

    /// Particles per row.
    pub fn row_length(&self) -> usize {
        // Width and spacing are checked positive and finite when the emitter is added.
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a positive ratio of checked lengths"
        )]
        let row = (self.width / self.spacing).floor() as usize;
        row.max(1)
    }

    /// Advances the emitter over a substep from `time` of length `dt`, pushing the positions and
    /// velocity of the particles it releases.
    pub(super) fn emit(&mut self, time: f64, dt: f64, out: &mut Vec<([f64; 2], [f64; 2])>) {
        if time < self.start || time >= self.stop || self.released >= self.budget {
            return;
        }
        let velocity = [
            self.direction[0] * self.speed,
            self.direction[1] * self.speed,
        ];
        let across = [-self.direction[1], self.direction[0]];
        let row = self.row_length();
        while self.travelled >= self.spacing && self.released < self.budget {
            self.travelled -= self.spacing;
            // The row laid now has already moved `travelled` past the segment.
            let ahead = self.travelled;
            for k in 0..row.min(self.budget - self.released) {
                let offset = (k as f64 + 0.5) * self.spacing - row as f64 * self.spacing / 2.0;
                out.push((
                    [
                        self.center[0] + across[0] * offset + self.direction[0] * ahead,
                        self.center[1] + across[1] * offset + self.direction[1] * ahead,
                    ],
                    velocity,
                ));
                self.released += 1;
            }
        }
        self.travelled += self.speed * dt;
    }

    /// Checks the numbers.
    pub(super) fn is_valid(&self) -> bool {
        let finite = [
            self.center[0],
            self.center[1],
            self.direction[0],
            self.direction[1],
            self.width,
            self.speed,
            self.spacing,
            self.start,
        ]
        .iter()
        .all(|value| value.is_finite());
        let unit =
            ((self.direction[0].powi(2) + self.direction[1].powi(2)).sqrt() - 1.0).abs() < 1e-9;
        finite
            && unit
            && self.width > 0.0
            && self.speed > 0.0
            && self.spacing > 0.0
            && !self.stop.is_nan()
    }
}

//! The ball scene (`soft_body`): objects from the annotation's layout; materials and pit
//! outcomes from its records (`--dynamics annotation`, the paper's offline mode).
//!
//! Input: a video's `outputs.json` ([`BallAnnotation`]); under `--dynamics simulate` also its
//! tracked particles (`outputs4D.json`), or under `--perception maskrcnn` its frames. Output:
//! the scene's objects and the answers of `query`, `register_event` and `happen`
//! (`docs/data/ball.md`). Under `--dynamics simulate` the materials are read from the tracked
//! particles ([`infer`]) and the runs are simulated ([`simulate`], made on first use by `runs`);
//! the annotation gives only the layout. Under `--perception maskrcnn` the detector's masks give
//! the stadium and the balls' paths (`perceived`), and of the annotation only the camera
//! calibration is read (with `--dynamics annotation`, also the recorded outcomes, keyed by the
//! names perception must read right).
//!
//! Objects, in this order: the balls (`Red Ball`), the floating walls (`White Floating Wall`),
//! the ramps (`Right Ramp`, `Left Ramp`: kind `ramp`, their colour, `side` right or left), then
//! the two pits (`Left Pit`, `Right Pit`: kind `pit`, no colour, `side` left or right). The floor
//! pieces are not objects (the pits are what lies between them).
//!
//! Answers agree with the question engine (`dataset::engine::ball`) by construction, reading
//! the same keys with the same rules:
//!
//! * `elasticity` and `plasticity` are scores of the release's materials: elasticity 1 for the
//!   `Elastic` ball, 0 for the `Rigid` and `Plastic` ones; plasticity 1 for the `Plastic` ball,
//!   0 for the others. `query_pair` gives `(None, None)` for two balls the materials do not
//!   order (rigid and plastic on elasticity, elastic and rigid on plasticity).
//! * events: `register_event([], 'simulate', '')` is the factual run; `register_event([],
//!   'remove', 'red floating wall and other balls')` (or the wall as the object) is the run
//!   without that wall in which the ball `happen` asks about is alone.
//! * `happen([ball], 'droping', [pit])`: the run's `pitResult` for the ball names that pit
//!   (observed in the video or after it).

pub mod infer;
mod perceived;
pub(crate) mod physics_bench;
mod reading_check;
mod runs;
mod silhouette;
pub mod simulate;
#[cfg(test)]
mod tests;

use std::path::PathBuf;
use std::sync::{Mutex, OnceLock, PoisonError};

pub use reading_check::scene_report;
use runs::{BallRuns, RunKey, SeenBall};
use simulate::{BallModel, Stadium};

use crate::dataset::ball::names::parse_ball_object_name;
use crate::dataset::ball::outcome::{Pit, PitRecord};
use crate::dataset::ball::{BallAnnotation, ElasticityType, VOCABULARY};
use crate::dataset::{FourDData, Scenario};
use crate::perception::ball::PERCEPTION;
use crate::scene_api::perceiver::{Perceiver, calibration, kept_work};
use crate::scene_api::{
    ApiError, DynamicsBackend, EventAction, ObjectId, PerceptionBackend, Property, ScenarioBackend,
    SceneEvent, SceneObjectInfo, Target, VideoSpec, misuse, named_nothing, resolve_description,
    unknown_action,
};

/// The vocabulary attribute that tells the pits apart.
const SIDE: &str = "side";
/// The words a removal names besides its wall (`red floating wall and other balls`).
const AND_OTHER_BALLS: &str = " and other balls";

/// Loads the backend of a ball video (the scenario table's scene backend for ball).
pub fn load(spec: &VideoSpec) -> Result<Box<dyn ScenarioBackend>, ApiError> {
    let annotation = BallAnnotation::load(&spec.video_dir.join("outputs.json"))?;
    if spec.perception == PerceptionBackend::Annotation {
        let mut backend = BallBackend::new(annotation);
        if spec.dynamics == DynamicsBackend::Simulate {
            backend.simulate_from = Some(spec.video_dir.clone());
        }
        return Ok(Box::new(backend));
    }
    // `--perception maskrcnn`: of the annotation only the camera calibration is read, unless
    // the dynamics are the annotation's (whose recorded runs are keyed by its names).
    let camera = calibration(annotation.camera.as_ref())?.clone();
    let mut perceiver = Perceiver::open_for(spec, PERCEPTION.classes, &VOCABULARY)?;
    let perceived = perceived::perceive_scene(&mut perceiver, &camera)?;
    perceiver.set_names(perceived.names.clone());
    let backend = match spec.dynamics {
        DynamicsBackend::Simulate => {
            let mut backend = BallBackend::new(perceived.annotation);
            backend.simulate_from = Some(spec.video_dir.clone());
            backend.perceiver = Some(Mutex::new(perceiver));
            backend.from_pixels = true;
            backend
        }
        DynamicsBackend::Annotation => {
            // The objects perception did not read (a ball or wall in another colour, a ramp
            // not seen) are not the annotated ones, whose outcomes are keyed by name.
            let mut backend = BallBackend::new(annotation);
            backend.from_pixels = true;
            let seen = BallBackend::new(perceived.annotation);
            for object in &mut backend.objects {
                object.visible = object.kind == "pit"
                    || seen
                        .objects
                        .iter()
                        .any(|other| other.name == object.name && other.color == object.color);
            }
            backend
        }
    };
    Ok(Box::new(backend))
}

/// What an object of the scene stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    /// A ball, its material in the annotation and its index among the balls.
    Ball(ElasticityType, usize),
    /// A floating wall and its index among the floating walls.
    Wall(usize),
    /// A ramp, on the side of this pit.
    Ramp(Pit),
    /// A pit.
    Pit(Pit),
}

/// One ball video's answers, from its annotations.
pub(crate) struct BallBackend {
    annotation: BallAnnotation,
    objects: Vec<SceneObjectInfo>,
    roles: Vec<Role>,
    /// The video folder under `--dynamics simulate` (its tracked particles are read on first
    /// use); `None` answers from the annotation.
    simulate_from: Option<PathBuf>,
    /// The simulated runs, set up on first use.
    runs: OnceLock<Result<BallRuns, ApiError>>,
    /// The video as the detector sees it (`--perception maskrcnn --dynamics simulate`): the
    /// balls' paths are read from its masks instead of the tracked particles.
    perceiver: Option<Mutex<Perceiver>>,
    /// Whether the objects were read from pixels (`--perception maskrcnn`): a name no object
    /// carries may then be a perception miss (`not_seen`) rather than the program's misuse.
    from_pixels: bool,
}

/// The run an event starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Run<'a> {
    /// The factual run.
    Factual,
    /// The run without this floating wall (each ball alone).
    Without(&'a SceneObjectInfo),
}

impl BallBackend {
    /// The backend of `annotation`.
    pub(crate) fn new(annotation: BallAnnotation) -> BallBackend {
        let mut named: Vec<(String, String, Role)> = Vec::new();
        let color_of = |name: &str| parse_ball_object_name(name).and_then(|parsed| parsed.color);
        for (index, ball) in annotation.layout.balls.iter().enumerate() {
            if let Some(color) = color_of(&ball.name) {
                named.push((
                    ball.name.clone(),
                    color.to_string(),
                    Role::Ball(ball.elasticity, index),
                ));
            }
        }
        for (index, wall) in annotation.layout.floating_walls.iter().enumerate() {
            if let Some(color) = color_of(&wall.name) {
                named.push((wall.name.clone(), color.to_string(), Role::Wall(index)));
            }
        }
        for ramp in &annotation.layout.ramps {
            let color = crate::dataset::palette::palette_name(i64::from(ramp.color));
            let side = if ramp.name.starts_with("Left") {
                Pit::Left
            } else {
                Pit::Right
            };
            if let Some(color) = color {
                named.push((ramp.name.clone(), color.to_string(), Role::Ramp(side)));
            }
        }
        for pit in Pit::BOTH {
            let name = match pit {
                Pit::Left => "Left Pit",
                Pit::Right => "Right Pit",
            };
            named.push((name.to_string(), String::new(), Role::Pit(pit)));
        }
        let (objects, roles) = named
            .into_iter()
            .enumerate()
            .map(|(index, (name, color, role))| {
                let side = |pit: Pit| vec![(SIDE, pit.word().to_string())];
                let (kind, attributes) = match role {
                    Role::Ball(..) => ("ball", Vec::new()),
                    Role::Wall(_) => ("floating wall", Vec::new()),
                    Role::Ramp(pit) => ("ramp", side(pit)),
                    Role::Pit(pit) => ("pit", side(pit)),
                };
                let object = SceneObjectInfo::new(
                    ObjectId(u32::try_from(index).unwrap_or(u32::MAX)),
                    &name,
                    &color.to_lowercase(),
                    kind,
                    &attributes,
                    &VOCABULARY,
                );
                (object, role)
            })
            .unzip();
        BallBackend {
            annotation,
            objects,
            roles,
            simulate_from: None,
            runs: OnceLock::new(),
            perceiver: None,
            from_pixels: false,
        }
    }

    /// The simulated runs (`--dynamics simulate`), set up on first use: the stadium from the
    /// layout, each ball's motion (and, from its tracked particles, material) from the video.
    fn simulated_runs(&self, folder: &std::path::Path) -> Result<&BallRuns, ApiError> {
        self.runs
            .get_or_init(|| {
                let mut balls = match &self.perceiver {
                    Some(perceiver) => {
                        let mut perceiver =
                            perceiver.lock().unwrap_or_else(PoisonError::into_inner);
                        self.balls_from_pixels(&mut perceiver)?
                    }
                    None => self.balls_from_particles(folder)?,
                };
                let stadium = Stadium::from_layout(&self.annotation.layout);
                let model = BallModel::default();
                let work = runs::fit_materials(&stadium, &mut balls, &model)?;
                Ok(BallRuns::new(stadium, balls, model, work))
            })
            .as_ref()
            .map_err(Clone::clone)
    }

    /// Each ball's path from the detector's masks over the whole video (no material: the fit
    /// decides).
    fn balls_from_pixels(&self, perceiver: &mut Perceiver) -> Result<Vec<SeenBall>, ApiError> {
        let camera = calibration(self.annotation.camera.as_ref())?;
        let (width, height, _) = perceiver.frames();
        let model = perceived::camera_model(camera, (width, height));
        perceived::seen_balls(perceiver, &self.annotation.layout, &model)
    }

    /// Each ball's path and material from its tracked particles (`outputs4D.json` in `folder`).
    fn balls_from_particles(&self, folder: &std::path::Path) -> Result<Vec<SeenBall>, ApiError> {
        let path = folder.join("outputs4D.json");
        let four_d = FourDData::load(&path).map_err(|error| {
            ApiError::Unavailable(format!(
                "--dynamics simulate reads the balls' tracked particles: {error}"
            ))
        })?;
        let names: Vec<String> = self
            .annotation
            .layout
            .balls
            .iter()
            .map(|ball| ball.name.clone())
            .collect();
        let readings = infer::read_materials(&four_d, &names);
        let mut balls = Vec::with_capacity(names.len());
        for (name, reading) in names.iter().zip(readings) {
            let track = four_d.soft_bodies.get(name).ok_or_else(|| {
                ApiError::Unavailable(format!(
                    "{} has no tracked particles for the {}",
                    path.display(),
                    name.to_lowercase()
                ))
            })?;
            let seen = SeenBall::from_track(name, reading.material, &track.particles).ok_or_else(
                || {
                    ApiError::Unavailable(format!(
                        "the {} is tracked in fewer than two frames",
                        name.to_lowercase()
                    ))
                },
            )?;
            balls.push(seen);
        }
        Ok(balls)
    }

    /// The material `query` compares for ball `index`: the annotation's, or under `--dynamics
    /// simulate` the one read from the tracked particles.
    fn material_of(
        &self,
        recorded: ElasticityType,
        index: usize,
        object: &SceneObjectInfo,
    ) -> Result<ElasticityType, ApiError> {
        let Some(folder) = &self.simulate_from else {
            return Ok(recorded);
        };
        let runs = self.simulated_runs(folder)?;
        runs.material(index).ok_or_else(|| {
            ApiError::Unavailable(format!(
                "the video does not tell the {}'s material",
                object.describe()
            ))
        })
    }

    fn info(&self, id: ObjectId, function: &str) -> Result<&SceneObjectInfo, ApiError> {
        self.objects.get(id.0 as usize).ok_or_else(|| {
            misuse(format!(
                "{function}: object #{} does not belong to this scene",
                id.0
            ))
        })
    }

    fn role(&self, object: &SceneObjectInfo) -> Option<Role> {
        self.roles.get(object.id.0 as usize).copied()
    }

    /// The objects a description names, in `find`'s words.
    fn resolve(&self, description: &str, function: &str) -> Result<Vec<ObjectId>, ApiError> {
        let (_, found) = resolve_description(
            &self.objects,
            Scenario::Ball.name(),
            &VOCABULARY,
            description,
            function,
        )?;
        Ok(found)
    }

    /// The short names of the scene's objects of `kind`, for messages.
    fn names_of_kind(&self, kind: &str) -> String {
        let names: Vec<String> = self
            .objects
            .iter()
            .filter(|object| object.kind == kind)
            .map(SceneObjectInfo::describe)
            .collect();
        format!("the {kind}s are: {}", names.join(", "))
    }

    /// The one object of `kind` that `ids` name, for `function`'s messages about `what`.
    fn one_of_kind(
        &self,
        ids: &[ObjectId],
        kind: &str,
        function: &str,
        what: &str,
    ) -> Result<&SceneObjectInfo, ApiError> {
        match ids {
            [one] => {
                let object = self.info(*one, function)?;
                if object.kind == kind {
                    Ok(object)
                } else {
                    Err(misuse(format!(
                        "{function}: {what} takes a {kind}, not the {}",
                        object.describe()
                    )))
                }
            }
            [] => Err(named_nothing(
                format!(
                    "{function}: {what} names no {kind} (an empty list: `find` found no such object); {}",
                    self.names_of_kind(kind)
                ),
                self.from_pixels,
            )),
            many => Err(misuse(format!(
                "{function}: {what} takes one {kind}, got {} objects",
                many.len()
            ))),
        }
    }

    /// The run `event` starts.
    fn event_run(&self, event: &SceneEvent, function: &str) -> Result<Run<'_>, ApiError> {
        match event.action {
            EventAction::Simulate => Ok(Run::Factual),
            EventAction::Remove => {
                let attribute = event.attribute.trim().to_lowercase();
                let description = attribute
                    .strip_suffix(AND_OTHER_BALLS)
                    .unwrap_or(&attribute)
                    .trim();
                let plain = description.is_empty() || description == "floating wall";
                let ids = if !event.attribute_objects.is_empty() {
                    event.attribute_objects.clone()
                } else if let (Some(object), true) = (event.object, plain) {
                    vec![object]
                } else {
                    self.resolve(description, function)?
                };
                if ids.is_empty() && !plain {
                    return Err(misuse(format!(
                        "{function}: `{description}` names no floating wall of this scene; {}",
                        self.names_of_kind("floating wall")
                    )));
                }
                let wall = self.one_of_kind(&ids, "floating wall", function, "'remove'")?;
                Ok(Run::Without(wall))
            }
            EventAction::Increase | EventAction::Decrease | EventAction::Emit => {
                Err(misuse(format!(
                    "{function}: ball scenes support register_event([], 'remove', 'red floating wall and other balls') \
                     and register_event([], 'simulate', '')"
                )))
            }
        }
    }

    /// The outcome of `ball` in `run`.
    fn record(&self, run: Run<'_>, ball: &SceneObjectInfo) -> Result<PitRecord, ApiError> {
        match run {
            Run::Factual => self
                .annotation
                .tracking
                .get(&ball.name)
                .copied()
                .ok_or_else(|| {
                    ApiError::Unavailable(format!(
                        "happen: the video records no outcome of the {}",
                        ball.describe()
                    ))
                }),
            Run::Without(wall) => self
                .annotation
                .counterfactual(&wall.name, &ball.name)
                .map(|run| run.record)
                .ok_or_else(|| {
                    ApiError::Unavailable(format!(
                        "happen: this video has no run of the {} without the {}",
                        ball.describe(),
                        wall.describe()
                    ))
                }),
        }
    }

    /// Whether a ball of `material` scores 1 on `property` (see the module docs).
    fn high(property: Property, material: ElasticityType) -> bool {
        match property {
            Property::Plasticity => material == ElasticityType::Plastic,
            _ => material == ElasticityType::Elastic,
        }
    }
}

impl ScenarioBackend for BallBackend {
    fn objects(&self) -> &[SceneObjectInfo] {
        &self.objects
    }

    fn query(
        &self,
        property: Property,
        objects: &[ObjectId],
        function: &str,
    ) -> Result<Vec<Option<f64>>, ApiError> {
        if !matches!(property, Property::Elasticity | Property::Plasticity) {
            return Err(misuse(format!(
                "{function}: property `{}` does not apply to ball scenes; ball scenes have elasticity and plasticity (balls)",
                property.name()
            )));
        }
        let mut materials = Vec::with_capacity(objects.len());
        for id in objects {
            let object = self.info(*id, function)?;
            let Some(Role::Ball(recorded, index)) = self.role(object) else {
                return Err(misuse(format!(
                    "{function}: {} is a property of balls, not of the {}",
                    property.name(),
                    object.describe()
                )));
            };
            materials.push(self.material_of(recorded, index, object)?);
        }
        let high: Vec<bool> = materials
            .iter()
            .map(|material| Self::high(property, *material))
            .collect();
        if let ([first, second], [a, b]) = (materials.as_slice(), high.as_slice())
            && first != second
            && a == b
        {
            // Two materials the release's do not order on this property.
            return Ok(vec![None, None]);
        }
        Ok(high
            .into_iter()
            .map(|high| Some(if high { 1.0 } else { 0.0 }))
            .collect())
    }

    fn simulation_work(&self) -> (u64, u64) {
        match self.runs.get() {
            Some(Ok(runs)) => runs.work(),
            _ => (0, 0),
        }
    }

    fn perception_work(&self) -> (u64, u64) {
        kept_work(self.perceiver.as_ref())
    }

    fn check_event(&self, event: &SceneEvent) -> Result<(), ApiError> {
        self.event_run(event, "register_event").map(|_| ())
    }

    fn happen(
        &self,
        event: &SceneEvent,
        object: ObjectId,
        action: &str,
        target: &Target,
    ) -> Result<bool, ApiError> {
        let subject = self.info(object, "happen")?;
        match action {
            "droping" | "dropping" | "drop" | "drops" | "drop into" | "dropping into"
            | "falling into" => {}
            "entering" | "passing" | "motion" | "rotation" | "collision" | "falling"
            | "touching" => {
                return Err(misuse(format!(
                    "happen: `{action}` belongs to other scenarios; ball scenes answer 'droping' (into a pit)"
                )));
            }
            _ => {
                return Err(unknown_action(action, "ball", "droping"));
            }
        }
        let Some(Role::Ball(_, ball_index)) = self.role(subject) else {
            return Err(misuse(format!(
                "happen: only balls drop into pits; ask about a ball, not the {}",
                subject.describe()
            )));
        };
        let ids = match target {
            Target::Objects(ids) => ids.clone(),
            Target::Text(text) if text.trim().is_empty() => {
                return Err(misuse(
                    "happen: 'droping' needs the pit, e.g. happen([ball], 'droping', ball_scene.find('left pit'))",
                ));
            }
            Target::Text(text) => self.resolve(text, "happen")?,
        };
        let pit = self.one_of_kind(&ids, "pit", "happen", "'droping'")?;
        let Some(Role::Pit(side)) = self.role(pit) else {
            return Err(misuse("happen: 'droping' takes a pit"));
        };
        let run = self.event_run(event, "happen")?;
        if let Some(folder) = &self.simulate_from {
            let key = match run {
                Run::Factual => RunKey::Factual,
                Run::Without(wall) => match self.role(wall) {
                    Some(Role::Wall(wall)) => RunKey::Without {
                        wall,
                        ball: ball_index,
                    },
                    _ => return Err(misuse("happen: 'remove' takes a floating wall")),
                },
            };
            return Ok(self.simulated_runs(folder)?.pit(key, ball_index)? == Some(side));
        }
        Ok(self.record(run, subject)?.result.pit() == Some(side))
    }
}

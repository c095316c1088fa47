//! The rope scene: objects from the annotation names; with `--dynamics annotation` (the
//! paper's offline mode) masses from `outputMass` and motion/rotation from the factual results
//! (`simulate`) or the mass counterfactual runs (`increase`/`decrease` of a load's mass); with
//! `--dynamics simulate` motion/rotation from simulated runs and masses inferred from the
//! tracked motion (`rope_sim`), as ContPRO does.
//!
//! Units: mass in kg (the benchmark's nominal mass, `ceil(m·100)/100`, so loads under a movable
//! pulley read exactly double, see `dataset::engine::EngineObject`); tension in N (the weight of
//! the load the rope carries, `m·g` with g = 9.81 m/s²), which is what the benchmark's tension
//! questions compare. Inferred masses are the best-explaining candidates, and a pair reads
//! "cannot tell" (`None`) unless the motion decides how the two compare.

use indexmap::IndexMap;

use std::collections::BTreeMap;
use std::sync::{Mutex, OnceLock, PoisonError};

mod evidence;
mod hanging;
mod inference_bench;
mod masses;
mod mechanism_check;
mod perceived;
pub mod simulation;
mod topology;

pub use inference_bench::inference_report;
pub use mechanism_check::{
    MATCH_RADIUS, MechanismCheck, MissedRope, check_rope_mechanism, mechanism_report,
};

use self::perceived::perceive_mechanism;
use self::simulation::{RopeMassInference, RopeOutcome, Run, load_multiplier, simulate_rope};
use crate::dataset::engine::rope::RopeScene;
use crate::dataset::rope::VOCABULARY;
use crate::dataset::rope::{
    RopeAnnotation, RopeChange, RopeCounterfactual, RopeObjectKind, RopeObjectName,
    parse_rope_object_name, world,
};
use crate::dataset::{Camera, FourDData};
use crate::perception::rope::PERCEPTION;
use crate::scene_api::perceiver::{PerceivedScene, Perceiver, kept_work};
use crate::scene_api::{ApiError, ObjectId, SceneObjectInfo, misuse, unknown_action};
use crate::scene_api::{
    DynamicsBackend, EventAction, PerceptionBackend, Property, ScenarioBackend, SceneEvent, Target,
    VideoSpec,
};

/// The motion and rotation results of one dynamic scene (name → −1, 0, +1).
type Outcomes = (IndexMap<String, i8>, IndexMap<String, i8>);

/// The scene object at `index` named `name`, with the words of `parsed` (its parsed name; a
/// name outside the grammar keeps the engine's colour and kind, `fallback`).
fn object_info(
    index: usize,
    name: &str,
    parsed: Option<&RopeObjectName>,
    fallback: (&str, RopeObjectKind, &str),
) -> SceneObjectInfo {
    let (color, kind, dynamics) = fallback;
    let mut attributes = vec![("dynamic", dynamics.to_string())];
    if let Some(parsed) = parsed {
        if let Some(shape) = &parsed.pulley_shape {
            attributes.push(("shape", shape.clone()));
        }
        if let Some((layer, column)) = parsed.grid {
            attributes.push(("grid", format!("{layer} {column}")));
        }
    }
    SceneObjectInfo::new(
        ObjectId(u32::try_from(index).unwrap_or(u32::MAX)),
        name,
        color,
        kind.word(),
        &attributes,
        &VOCABULARY,
    )
}

/// Standard gravity, m/s².
const GRAVITY_M_PER_S2: f64 = 9.81;

/// Loads the backend of a rope video (the scenario table's scene backend for rope).
pub fn load(spec: &VideoSpec) -> Result<Box<dyn ScenarioBackend>, ApiError> {
    Ok(Box::new(RopeBackend::load(spec)?))
}

/// One rope video's answers: objects from the annotation (or from pixels), masses, tensions and
/// dynamic outcomes from the annotations or from simulation.
pub(crate) struct RopeBackend {
    annotation: RopeAnnotation,
    /// The question engine's view of the video: object order, nominal masses, related loads and
    /// the load → rope map, shared so answers and questions agree by construction.
    structure: RopeScene,
    objects: Vec<SceneObjectInfo>,
    /// Related group of each rope (index into `relatedGroupsInRope`).
    rope_group: Vec<Option<usize>>,
    /// Tension per object (ropes only), N; `None` when the rope carries no load or loads of
    /// different masses (the video cannot tell one value).
    tension_n: Vec<Option<f64>>,
    /// Where motion and rotation answers come from.
    dynamics: DynamicsBackend,
    /// The tracked rope particles (for `Simulate`: which side ropes pass pulleys on).
    four_d: Option<FourDData>,
    /// Simulated runs so far, by (event action, object): a scene simulates only the runs its
    /// questions ask about, once each.
    simulated: Mutex<BTreeMap<(u8, Option<u32>), RopeOutcome>>,
    /// Simulator runs and steps done, for the work counters.
    simulation_work: Mutex<(u64, u64)>,
    /// The masses inferred from the tracked motion (`Simulate`), on first use.
    inference: OnceLock<Result<RopeMassInference, ApiError>>,
    /// The video as the detector sees it (`--perception maskrcnn`): it named the objects, and
    /// its tracks stand for the annotated ones in mass inference.
    perceiver: Option<Mutex<Perceiver>>,
    /// Whether the annotation itself was read from pixels (`--perception maskrcnn --dynamics
    /// simulate`): then it records no masses, and the factual run takes the inferred ones.
    perceived_mechanism: bool,
}

impl RopeBackend {
    /// The backend of one rope video, as the scenario table's [`load`] builds it.
    pub(crate) fn load(spec: &VideoSpec) -> Result<RopeBackend, ApiError> {
        let video_dir = spec.video_dir.as_path();
        let annotation = RopeAnnotation::load(&video_dir.join("outputs.json"))?;
        let dynamics = spec.dynamics;
        let perceiver = match spec.perception {
            PerceptionBackend::MaskRcnn => {
                Some(Perceiver::open_for(spec, PERCEPTION.classes, &VOCABULARY)?)
            }
            PerceptionBackend::Annotation => None,
        };
        let perceiver = match perceiver {
            Some(perceiver) if dynamics == DynamicsBackend::Simulate => {
                return RopeBackend::perceived(spec, perceiver, annotation.camera);
            }
            other => other,
        };
        let mut backend = RopeBackend::new(annotation, &spec.video_id)?;
        backend.dynamics = dynamics;
        if let Some(mut perceiver) = perceiver {
            backend.apply_perception(&perceiver.scene()?);
            backend.perceiver = Some(Mutex::new(perceiver));
        }
        if dynamics == DynamicsBackend::Simulate {
            let path = video_dir.join("outputs4D.json");
            if path.is_file() {
                backend.four_d = Some(FourDData::load(&path)?);
            }
        }
        Ok(backend)
    }

    /// ContPRO (`--perception maskrcnn --dynamics simulate`): the mechanism itself comes from
    /// pixels; of the annotations only the camera calibration is read.
    fn perceived(
        spec: &VideoSpec,
        mut perceiver: Perceiver,
        camera: Option<Camera>,
    ) -> Result<RopeBackend, ApiError> {
        let camera = camera.ok_or_else(|| {
            ApiError::Unavailable(
                "perception needs the camera calibration (outputCamera), which this video lacks"
                    .to_string(),
            )
        })?;
        let perceived = perceive_mechanism(&mut perceiver, &camera)?;
        let mut backend = RopeBackend::new(perceived.annotation, &spec.video_id)?;
        backend.add_unattached(&perceived.unattached);
        backend.dynamics = DynamicsBackend::Simulate;
        backend.four_d = Some(perceived.four_d);
        backend.perceived_mechanism = true;
        backend.perceiver = Some(Mutex::new(perceiver));
        Ok(backend)
    }

    pub(crate) fn new(annotation: RopeAnnotation, video_id: &str) -> Result<RopeBackend, ApiError> {
        let structure = RopeScene::from_annotation(video_id, &annotation)
            .map_err(|error| ApiError::Data(error.to_string()))?;
        let objects: Vec<SceneObjectInfo> = structure
            .objects()
            .iter()
            .enumerate()
            .map(|(index, object)| {
                let parsed = parse_rope_object_name(&object.annotation_name);
                object_info(
                    index,
                    &object.annotation_name,
                    parsed.as_ref(),
                    (&object.color, object.kind, &object.dynamics),
                )
            })
            .collect();
        let rope_group = objects
            .iter()
            .map(|o| {
                (o.kind == "rope")
                    .then(|| {
                        annotation
                            .related_groups_in_rope
                            .iter()
                            .position(|g| g.contains_key(&o.name))
                    })
                    .flatten()
            })
            .collect();
        let tension_n = (0..objects.len())
            .map(|rope| {
                if objects[rope].kind != "rope" {
                    return None;
                }
                let masses: Vec<f64> = structure
                    .loads()
                    .filter(|load| structure.rope_of(*load) == Some(rope))
                    .filter_map(|load| structure.object(load).and_then(|o| o.nominal_mass_kg))
                    .collect();
                let first = *masses.first()?;
                masses
                    .iter()
                    .all(|m| (m - first).abs() < 1e-9)
                    .then_some(first * GRAVITY_M_PER_S2)
            })
            .collect();
        Ok(RopeBackend {
            annotation,
            structure,
            objects,
            rope_group,
            tension_n,
            dynamics: DynamicsBackend::Annotation,
            four_d: None,
            simulated: Mutex::new(BTreeMap::new()),
            simulation_work: Mutex::new((0, 0)),
            inference: OnceLock::new(),
            perceiver: None,
            perceived_mechanism: false,
        })
    }

    /// Adds objects perception saw on no rope it could read: findable by their words, outside
    /// the mechanism.
    fn add_unattached(&mut self, names: &[String]) {
        for name in names {
            let Some(parsed) = parse_rope_object_name(name) else {
                continue;
            };
            self.objects.push(object_info(
                self.objects.len(),
                name,
                Some(&parsed),
                (&parsed.color, parsed.kind, &parsed.dynamics),
            ));
            self.rope_group.push(None);
            self.tension_n.push(None);
        }
    }

    /// Replaces the objects' words with what perception saw; objects it did not see are hidden
    /// from `find`.
    fn apply_perception(&mut self, perceived: &PerceivedScene) {
        for object in &mut self.objects {
            match perceived
                .objects
                .iter()
                .find(|(name, _)| *name == object.name)
            {
                Some((_, words)) => {
                    let attribute = |name: &str| {
                        words
                            .attributes
                            .iter()
                            .find(|(attribute, _)| *attribute == name)
                            .map(|(_, value)| (*value).to_string())
                    };
                    object.color.clone_from(&words.color);
                    object.kind = words.kind;
                    object.set_attribute("shape", attribute("shape"));
                    // Loads, ropes and fixed points keep the annotation's dynamics; only a
                    // pulley's class says whether it is static or movable.
                    if object.kind == RopeObjectKind::Pulley.word() {
                        object.set_attribute("dynamic", attribute("dynamic"));
                    }
                    object.visible = true;
                }
                None => object.visible = false,
            }
        }
    }

    fn info(&self, id: ObjectId, function: &str) -> Result<&SceneObjectInfo, ApiError> {
        self.objects.get(id.0 as usize).ok_or_else(|| {
            misuse(format!(
                "{function}: object #{} does not belong to this scene",
                id.0
            ))
        })
    }

    /// Whether the video can compare two objects: loads in the same related group, or ropes of
    /// the same group.
    fn comparable(&self, first: &SceneObjectInfo, second: &SceneObjectInfo) -> bool {
        let (a, b) = (first.id.0 as usize, second.id.0 as usize);
        if first.kind == "rope" {
            self.rope_group[a].is_some() && self.rope_group[a] == self.rope_group[b]
        } else {
            a == b || self.structure.are_related(a, b)
        }
    }

    /// The results (motion, rotation) of the dynamic scene started by `event`.
    fn results(&self, event: &SceneEvent) -> Result<Outcomes, ApiError> {
        if self.dynamics == DynamicsBackend::Simulate {
            return self.simulated_results(event);
        }
        match event.action {
            EventAction::Simulate => Ok((
                self.annotation.result_motion.clone(),
                self.annotation.result_rotation.clone(),
            )),
            EventAction::Increase | EventAction::Decrease => {
                let load = self.info(
                    event
                        .object
                        .ok_or_else(|| misuse("an increase/decrease event needs an object"))?,
                    "init_dyn_simulation",
                )?;
                let lighter = event.action == EventAction::Decrease;
                let run: Option<&RopeCounterfactual> = self.annotation.mass_counterfactuals().find(|cf| {
                    matches!(&cf.change, RopeChange::Mass { target, .. } if *target == load.name)
                        && cf.change.is_lighter() == Some(lighter)
                });
                let run = run.ok_or_else(|| {
                    ApiError::Unavailable(format!(
                        "this video has no counterfactual run where the mass of the {} {}s",
                        load.describe(),
                        if lighter { "decrease" } else { "increase" }
                    ))
                })?;
                Ok((run.motion.clone(), run.rotation.clone()))
            }
            EventAction::Emit | EventAction::Remove => Err(event_misuse()),
        }
    }

    /// The results of `event` by simulation: the video's masses for the factual run; for a
    /// mass counterfactual, every load at the counterfactual baseline (0.2 kg × its multiplier)
    /// and the target 0.1 kg × multiplier lighter or heavier (`docs/data/rope.md`, timeline and
    /// outcome labels).
    fn simulated_results(&self, event: &SceneEvent) -> Result<Outcomes, ApiError> {
        let key = (event.action as u8, event.object.map(|o| o.0));
        if let Some(done) = self
            .simulated
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .get(&key)
        {
            return Ok((done.motion.clone(), done.rotation.clone()));
        }
        let (masses, run) = match event.action {
            EventAction::Simulate if self.perceived_mechanism => {
                (self.inferred_masses()?, Run::Factual)
            }
            EventAction::Simulate => (self.annotation.output_mass_kg.clone(), Run::Factual),
            EventAction::Increase | EventAction::Decrease => {
                let load = self.info(
                    event
                        .object
                        .ok_or_else(|| misuse("an increase/decrease event needs an object"))?,
                    "init_dyn_simulation",
                )?;
                let mut masses = self.counterfactual_baseline();
                let base = masses.get(&load.name).copied().ok_or_else(|| {
                    misuse(format!(
                        "init_dyn_simulation: the {} has no mass to change",
                        load.describe()
                    ))
                })?;
                let multiplier = base / world::BASELINE_MASS_KG;
                let step = world::COUNTERFACTUAL_MASS_STEP_KG * multiplier;
                let changed = if event.action == EventAction::Decrease {
                    base - step
                } else {
                    base + step
                };
                masses.insert(load.name.clone(), changed);
                (masses, Run::Counterfactual)
            }
            EventAction::Emit | EventAction::Remove => return Err(event_misuse()),
        };
        let outcome = simulate_rope(&self.annotation, self.four_d.as_ref(), &masses, None, run)
            .map_err(|error| {
                ApiError::Unavailable(format!("cannot simulate this video: {error}"))
            })?;
        let results = (outcome.motion.clone(), outcome.rotation.clone());
        {
            let mut work = self
                .simulation_work
                .lock()
                .unwrap_or_else(PoisonError::into_inner);
            work.0 += 1;
            work.1 += outcome.steps;
        }
        self.simulated
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .insert(key, outcome);
        Ok(results)
    }

    /// The masses of the counterfactual baseline: a recorded one when the video has one, else
    /// 0.2 kg per load times its multiplier (1.975 for a load hanging from a movable pulley:
    /// next to a `Dynamic Pulley` on its rope's path).
    fn counterfactual_baseline(&self) -> IndexMap<String, f64> {
        if let Some(pair) = self.annotation.counterfactuals.first() {
            return pair.baseline_mass_kg.clone();
        }
        self.annotation
            .output_mass_kg
            .keys()
            .map(|name| {
                let multiplier = load_multiplier(&self.annotation, name);
                (name.clone(), world::BASELINE_MASS_KG * multiplier)
            })
            .collect()
    }
}

fn event_misuse() -> ApiError {
    misuse(
        "register_event: rope scenes support register_event([load], 'increase' or 'decrease', 'mass') \
         for a cube or sphere, and register_event([], 'simulate', '')",
    )
}

impl ScenarioBackend for RopeBackend {
    fn simulation_work(&self) -> (u64, u64) {
        *self
            .simulation_work
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
    }

    fn perception_work(&self) -> (u64, u64) {
        kept_work(self.perceiver.as_ref())
    }

    fn objects(&self) -> &[SceneObjectInfo] {
        &self.objects
    }

    fn query(
        &self,
        property: Property,
        objects: &[ObjectId],
        function: &str,
    ) -> Result<Vec<Option<f64>>, ApiError> {
        let infos = objects
            .iter()
            .map(|id| self.info(*id, function))
            .collect::<Result<Vec<_>, _>>()?;
        let values: Vec<Option<f64>> = match property {
            Property::Mass => infos
                .iter()
                .map(|o| {
                    self.structure
                        .object(o.id.0 as usize)
                        .and_then(|e| e.nominal_mass_kg)
                        .map(Some)
                        .ok_or_else(|| {
                            misuse(format!(
                                "{function}: mass is known for cubes and spheres, not for the {}",
                                o.describe()
                            ))
                        })
                })
                .collect::<Result<_, _>>()?,
            Property::Tension => infos
                .iter()
                .map(|o| {
                    if o.kind == "rope" {
                        Ok(self.tension_n[o.id.0 as usize])
                    } else {
                        Err(misuse(format!(
                            "{function}: tension is a property of ropes, not of the {}",
                            o.describe()
                        )))
                    }
                })
                .collect::<Result<_, _>>()?,
            other => {
                return Err(misuse(format!(
                    "{function}: property `{}` does not apply to rope scenes; rope scenes have mass (cubes, spheres) and tension (ropes)",
                    other.name()
                )));
            }
        };
        if self.dynamics == DynamicsBackend::Simulate {
            return self.query_observed(property, &infos);
        }
        if let [first, second] = infos.as_slice() {
            // Objects in different mechanically coupled groups cannot be compared from the video
            // (the benchmark answers "can not answer").
            if !self.comparable(first, second) || values.iter().any(Option::is_none) {
                return Ok(vec![None, None]);
            }
        }
        Ok(values)
    }

    fn check_event(&self, event: &SceneEvent) -> Result<(), ApiError> {
        match event.action {
            EventAction::Simulate => Ok(()),
            EventAction::Increase | EventAction::Decrease => {
                let object = event.object.ok_or_else(|| {
                    misuse("register_event: increase/decrease needs the load as the first argument, e.g. register_event([cube], 'increase', 'mass')")
                })?;
                let info = self.info(object, "register_event")?;
                if !(info.kind == "cube" || info.kind == "sphere") {
                    return Err(misuse(format!(
                        "register_event: only the mass of a cube or sphere can change in rope scenes, not the {}",
                        info.describe()
                    )));
                }
                if !(event.attribute.is_empty() || event.attribute == "mass") {
                    return Err(misuse(format!(
                        "register_event: rope scenes change `mass`, not `{}`",
                        event.attribute
                    )));
                }
                Ok(())
            }
            EventAction::Emit | EventAction::Remove => Err(event_misuse()),
        }
    }

    fn happen(
        &self,
        event: &SceneEvent,
        object: ObjectId,
        action: &str,
        target: &Target,
    ) -> Result<bool, ApiError> {
        let info = self.info(object, "happen")?;
        let Target::Text(target) = target else {
            return Err(misuse(format!(
                "happen: in rope scenes the target of `{action}` is a word such as 'up', 'down', 'clockwise' or 'anti-clockwise', not objects"
            )));
        };
        let target = target.trim().to_lowercase();
        let (motion, rotation) = self.results(event)?;
        let (results, wanted) = match action {
            "motion" | "move" | "moving" => {
                if info.kind == "rope" {
                    return Err(misuse(
                        "happen: ropes have no motion result; ask about a load, pulley or fixed point",
                    ));
                }
                let wanted = match target.as_str() {
                    "up" | "move up" | "upward" | "upwards" => 1,
                    "down" | "move down" | "downward" | "downwards" => -1,
                    "stationary" | "none" | "not move" | "still" => 0,
                    _ => {
                        return Err(misuse(format!(
                            "happen: the target of 'motion' is 'up', 'down' or 'stationary', not `{target}`"
                        )));
                    }
                };
                (motion, wanted)
            }
            "rotation" | "rotate" | "rotating" => {
                if info.kind != "pulley" {
                    return Err(misuse(format!(
                        "happen: only pulleys rotate; the {} has no rotation result",
                        info.describe()
                    )));
                }
                let wanted = match target.as_str() {
                    "clockwise" | "rotate clockwise" => 1,
                    "anti-clockwise"
                    | "anticlockwise"
                    | "counter-clockwise"
                    | "counterclockwise"
                    | "rotate anti-clockwise" => -1,
                    "stationary" | "none" | "not rotate" => 0,
                    _ => {
                        return Err(misuse(format!(
                            "happen: the target of 'rotation' is 'clockwise', 'anti-clockwise' or 'stationary', not `{target}`"
                        )));
                    }
                };
                (rotation, wanted)
            }
            "entering" | "passing" | "collision" | "falling" | "touching" | "droping"
            | "dropping" => {
                return Err(misuse(format!(
                    "happen: `{action}` belongs to other scenarios; rope scenes answer 'motion' (up, down) and 'rotation' (clockwise, anti-clockwise)"
                )));
            }
            _ => {
                return Err(unknown_action(action, "rope", "motion, rotation"));
            }
        };
        let sign = results.get(&info.name).ok_or_else(|| {
            ApiError::Unavailable(format!(
                "this video has no {action} result for the {}",
                info.describe()
            ))
        })?;
        Ok(i32::from(*sign) == wanted)
    }
}

#[cfg(test)]
mod tests {
    //! Hand-derived expectations on the real rope video (eval/demo/pulley_group/0): masses
    //! 0.2 / 0.25 / 0.15 kg; the two cubes share the purple rope's group, the pink sphere hangs in
    //! the green rope's group; making the purple cube lighter lifts it and turns the blue and gray
    //! pulleys clockwise and the pink pulley anti-clockwise (CounterFactualAnnotations 2.0).
    use super::*;
    use crate::dataset::{Scenario, VideoId};
    use crate::scene_api::{DynamicsBackend, PerceptionBackend, Scene, VideoSpec};

    /// A rope scene of `spec` with rope's parts (the scenario table's rope row).
    fn open_rope_scene(spec: VideoSpec) -> Scene {
        Scene::open(
            spec,
            crate::scene_api::SceneParts {
                vocabulary: &VOCABULARY,
                all_vocabularies: &crate::scene_api::test_support::ALL_VOCABULARIES,
                backend: Some(load),
            },
        )
    }

    fn scene() -> Scene {
        scene_with(DynamicsBackend::Annotation)
    }

    fn scene_with(dynamics: DynamicsBackend) -> Scene {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/pulley_group/0");
        let video = crate::dataset::VideoFolder {
            scenario: Scenario::Rope,
            id: VideoId("0".into()),
            dir,
        };
        open_rope_scene(VideoSpec::new(
            &video,
            PerceptionBackend::Annotation,
            dynamics,
        ))
    }

    fn names(scene: &Scene, query: &str) -> Vec<String> {
        scene
            .find(query)
            .unwrap()
            .into_iter()
            .map(|id| scene.object(id).unwrap().describe())
            .collect()
    }

    fn one(scene: &Scene, query: &str) -> ObjectId {
        let found = scene.find(query).unwrap();
        assert_eq!(found.len(), 1, "{query}");
        found[0]
    }

    #[test]
    fn find_matches_colour_kind_shape_and_dynamics_words() {
        let scene = scene();
        assert_eq!(
            scene.work().annotation_loads,
            0,
            "opening a scene must not read anything"
        );
        let cases: [(&str, &[&str]); 10] = [
            (
                "purple",
                &["purple cube", "purple rope", "purple solid pulley"],
            ),
            (
                "pulley",
                &[
                    "blue solid pulley",
                    "gray hollow pulley",
                    "pink solid pulley",
                    "purple solid pulley",
                ],
            ),
            (
                "solid pulley",
                &[
                    "blue solid pulley",
                    "pink solid pulley",
                    "purple solid pulley",
                ],
            ),
            ("blue pulley", &["blue solid pulley"]),
            ("cubes", &["purple cube", "green cube"]),
            ("fixed point", &["brown fixed point"]),
            (
                "static pulley",
                &[
                    "blue solid pulley",
                    "gray hollow pulley",
                    "pink solid pulley",
                    "purple solid pulley",
                ],
            ),
            ("dynamic pulley", &[]),
            ("red cube", &[]),
            ("red container", &[]),
        ];
        for (query, expected) in cases {
            assert_eq!(names(&scene, query), expected, "{query}");
        }
        assert_eq!(scene.find("").unwrap().len(), 10);
        assert_eq!(
            names(&scene, "purple solid static pulley (1 0)"),
            ["purple solid pulley"]
        );
        assert_eq!(
            scene.work().annotation_loads,
            1,
            "the annotation is loaded once"
        );
        assert_eq!(scene.work().sim_runs, 0);
    }

    #[test]
    fn mass_and_tension_queries_follow_related_groups() {
        let scene = scene();
        let purple = one(&scene, "purple cube");
        let green = one(&scene, "green cube");
        let pink = one(&scene, "pink sphere");
        assert_eq!(
            scene.query_pair("mass", purple, green).unwrap(),
            (Some(0.2), Some(0.25))
        );
        assert_eq!(scene.query_pair("mass", green, pink).unwrap(), (None, None));
        assert_eq!(scene.query_single("mass", pink).unwrap(), Some(0.15));
        let purple_rope = one(&scene, "purple rope");
        let green_rope = one(&scene, "green rope");
        // Both cubes (different masses) hang on the purple rope: no single tension value.
        assert_eq!(scene.query_single("tension", purple_rope).unwrap(), None);
        let pink_weight = scene.query_single("tension", green_rope).unwrap().unwrap();
        assert!((pink_weight - 0.15 * 9.81).abs() < 1e-12);
        assert_eq!(
            scene
                .query_pair("tension", purple_rope, green_rope)
                .unwrap(),
            (None, None)
        );
        let pulley = one(&scene, "blue pulley");
        let cases = [
            (
                scene.query_single("mass", pulley).unwrap_err(),
                "mass is known for cubes and spheres, not for the blue solid pulley",
            ),
            (
                scene.query_single("tension", purple).unwrap_err(),
                "tension is a property of ropes",
            ),
            (
                scene.query_single("density", purple).unwrap_err(),
                "property `density` does not apply to rope scenes",
            ),
            (
                scene.query_single("weight", purple).unwrap_err(),
                "unknown property `weight`; properties are mass, tension",
            ),
        ];
        for (error, expected) in cases {
            assert_eq!(error.kind(), "misuse");
            assert!(
                error.to_string().contains(expected),
                "`{error}` lacks `{expected}`"
            );
        }
    }

    #[test]
    fn simulated_dynamics_infer_masses_from_the_tracked_motion() {
        // The cubes' tracked accelerations (0.269 and −0.267 units/s²) fit 0.2 kg against
        // 0.25 kg over the 1 kg disc pulleys best; 0.15 against 0.2 fits nearly as well, and
        // both say "less than", so the pair is decided. The pink sphere hangs from a ceiling
        // point: its mass does not show, and it is in another group anyway.
        let scene = scene_with(DynamicsBackend::Simulate);
        let purple = one(&scene, "purple cube");
        let green = one(&scene, "green cube");
        let pink = one(&scene, "pink sphere");
        assert_eq!(
            scene.query_pair("mass", purple, green).unwrap(),
            (Some(0.2), Some(0.25))
        );
        assert_eq!(
            scene.query_pair("mass", green, purple).unwrap(),
            (Some(0.25), Some(0.2))
        );
        assert_eq!(
            scene.query_pair("mass", purple, purple).unwrap(),
            (Some(0.2), Some(0.2))
        );
        for cube in [purple, green] {
            assert_eq!(scene.query_pair("mass", cube, pink).unwrap(), (None, None));
        }
        assert_eq!(scene.query_single("mass", purple).unwrap(), Some(0.2));
        assert_eq!(
            scene.query_single("mass", pink).unwrap(),
            None,
            "the annotation says 0.15 kg; the motion cannot tell"
        );
        let purple_rope = one(&scene, "purple rope");
        let green_rope = one(&scene, "green rope");
        assert_eq!(scene.query_single("tension", purple_rope).unwrap(), None);
        assert_eq!(scene.query_single("tension", green_rope).unwrap(), None);
        assert_eq!(
            scene
                .query_pair("tension", purple_rope, green_rope)
                .unwrap(),
            (None, None)
        );
        let error = scene
            .query_single("mass", one(&scene, "blue pulley"))
            .unwrap_err();
        assert_eq!(error.kind(), "misuse");
        // Inference solves the model at one instant per candidate; it runs no simulation.
        assert_eq!(scene.work().sim_runs, 0);
        assert_eq!(scene.work().sim_steps, 0);
    }

    #[test]
    fn simulated_masses_need_the_4d_tracks() {
        let dir = tempfile::tempdir().unwrap();
        let source =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/pulley_group/0");
        fs_err::copy(source.join("outputs.json"), dir.path().join("outputs.json")).unwrap();
        let video = crate::dataset::VideoFolder {
            scenario: Scenario::Rope,
            id: VideoId("0".into()),
            dir: dir.path().to_path_buf(),
        };
        let scene = open_rope_scene(VideoSpec::new(
            &video,
            PerceptionBackend::Annotation,
            DynamicsBackend::Simulate,
        ));
        let purple = one(&scene, "purple cube");
        let green = one(&scene, "green cube");
        let error = scene.query_pair("mass", purple, green).unwrap_err();
        assert_eq!(error.kind(), "unavailable", "{error}");
        assert!(error.to_string().contains("no outputs4D.json"), "{error}");
    }

    #[test]
    fn counterfactual_and_factual_outcomes_come_from_the_annotations() {
        let scene = scene();
        let purple = one(&scene, "purple cube");
        let green = one(&scene, "green cube");
        let pink = one(&scene, "pink sphere");
        let blue_pulley = one(&scene, "blue pulley");
        let pink_pulley = one(&scene, "pink pulley");
        let purple_pulley = one(&scene, "purple pulley");
        let lighter_purple = scene
            .register_event(&[purple], "decrease", "mass", vec![])
            .unwrap();
        let heavier_purple = scene
            .register_event(&[purple], "increase", "mass", vec![])
            .unwrap();
        let heavier_green = scene
            .register_event(&[green], "increase", "mass", vec![])
            .unwrap();
        let lighter_pink = scene
            .register_event(&[pink], "decrease", "mass", vec![])
            .unwrap();
        let factual = scene.register_event(&[], "simulate", "", vec![]).unwrap();
        let up = Target::Text("up".into());
        let down = Target::Text("down".into());
        let clockwise = Target::Text("clockwise".into());
        let anti = Target::Text("anti-clockwise".into());
        let still = Target::Text("stationary".into());
        let cases = [
            (&lighter_purple, purple, "motion", &up, true),
            (&lighter_purple, green, "motion", &down, true),
            (&lighter_purple, blue_pulley, "rotation", &clockwise, true),
            (&lighter_purple, pink_pulley, "rotation", &anti, true),
            (&lighter_purple, purple_pulley, "rotation", &still, true),
            (&heavier_purple, purple, "motion", &up, false),
            (&heavier_purple, purple, "motion", &down, true),
            (&heavier_purple, blue_pulley, "rotation", &anti, true),
            (&heavier_green, green, "motion", &down, true),
            (&heavier_green, pink_pulley, "rotation", &anti, true),
            (&lighter_pink, pink, "motion", &still, true),
            (&lighter_pink, pink, "motion", &up, false),
            (&factual, purple, "motion", &up, true),
            (&factual, green, "motion", &down, true),
            (&factual, blue_pulley, "rotation", &clockwise, true),
        ];
        for (index, (event, object, action, target, expected)) in cases.into_iter().enumerate() {
            assert_eq!(
                scene.happen(event, &[object], action, target).unwrap(),
                expected,
                "case {index}"
            );
        }
        assert_eq!(
            scene.work().sim_runs,
            0,
            "oracle dynamics read annotations, they do not simulate"
        );
    }

    #[test]
    fn misuse_explains_what_is_allowed() {
        let scene = scene();
        let purple = one(&scene, "purple cube");
        let rope = one(&scene, "purple rope");
        let pulley = one(&scene, "blue pulley");
        let factual = scene.register_event(&[], "simulate", "", vec![]).unwrap();
        let cases = [
            (
                scene
                    .register_event(&[pulley], "increase", "mass", vec![])
                    .unwrap_err(),
                "only the mass of a cube or sphere can change",
            ),
            (
                scene
                    .register_event(&[purple], "remove", "", vec![])
                    .unwrap_err(),
                "rope scenes support register_event([load]",
            ),
            (
                scene
                    .register_event(&[purple], "push", "", vec![])
                    .unwrap_err(),
                "unknown action `push`",
            ),
            (
                scene
                    .register_event(&[purple, rope], "increase", "mass", vec![])
                    .unwrap_err(),
                "one object at a time, got 2",
            ),
            (
                scene
                    .register_event(&[purple], "increase", "color", vec![])
                    .unwrap_err(),
                "rope scenes change `mass`, not `color`",
            ),
            (
                scene
                    .happen(&factual, &[rope], "motion", &Target::Text("up".into()))
                    .unwrap_err(),
                "ropes have no motion result",
            ),
            (
                scene
                    .happen(
                        &factual,
                        &[purple],
                        "rotation",
                        &Target::Text("clockwise".into()),
                    )
                    .unwrap_err(),
                "only pulleys rotate",
            ),
            (
                scene
                    .happen(&factual, &[purple], "motion", &Target::Text("left".into()))
                    .unwrap_err(),
                "'up', 'down' or 'stationary', not `left`",
            ),
            (
                scene
                    .happen(
                        &factual,
                        &[purple],
                        "entering",
                        &Target::Text(String::new()),
                    )
                    .unwrap_err(),
                "belongs to other scenarios",
            ),
            (
                scene
                    .happen(
                        &factual,
                        &[purple, rope],
                        "motion",
                        &Target::Text("up".into()),
                    )
                    .unwrap_err(),
                "one object at a time, got 2",
            ),
            (
                scene
                    .happen(&factual, &[], "motion", &Target::Text("up".into()))
                    .unwrap_err(),
                "one object at a time, got 0",
            ),
        ];
        for (index, (error, expected)) in cases.into_iter().enumerate() {
            assert_eq!(error.kind(), "misuse", "case {index}: {error}");
            assert!(
                error.to_string().contains(expected),
                "case {index}: `{error}` lacks `{expected}`"
            );
        }
    }

    #[test]
    fn broken_annotation_is_a_data_error_on_first_use() {
        let dir = tempfile::tempdir().unwrap();
        fs_err::write(
            dir.path().join("outputs.json"),
            r#"{"validity": true, "relatedGroups": []}"#,
        )
        .unwrap();
        let video = crate::dataset::VideoFolder {
            scenario: Scenario::Rope,
            id: VideoId("x".into()),
            dir: dir.path().to_path_buf(),
        };
        let scene = open_rope_scene(VideoSpec::new(
            &video,
            PerceptionBackend::Annotation,
            DynamicsBackend::Annotation,
        ));
        let error = scene.find("cube").unwrap_err().to_string();
        assert!(
            error.contains("field `relatedGroupsInRope` is missing"),
            "{error}"
        );
        assert_eq!(scene.find("cube").unwrap_err().kind(), "data");
        assert_eq!(
            scene.find("cube").unwrap_err().to_string(),
            error,
            "the failure is memoised"
        );
        assert_eq!(scene.work().annotation_loads, 1);
    }
}

//! Events and outcomes of fluid scenes: the run an event starts (`register_event`), and whether
//! a fluid passes a stick or enters a container in it (`happen`).
//!
//! | event | run |
//! |---|---|
//! | `register_event([], 'simulate', '')` | the factual run (its `trackingData`, 200 updates past the video) |
//! | `register_event(emitter, 'emit', 'fluid')` | the factual run, in which the emitter's fluid is the fluid of its colour |
//! | `register_event([], 'remove', 'green stick')`, `register_event(green_stick, 'remove', 'stick')` | the counterfactual run whose `removedStickName` is the stick |
//!
//! `happen([fluid or emitter], action, [target])` answers `passing` (a stick), `entering` (a
//! container) and `entering most` (strictly more of the fluid ends in that container than in
//! any other). The subject is a fluid, or an emitter standing for the fluid it emits; a later
//! emitter does not emit in counterfactual runs (the release re-simulates the first emitters
//! only).

use std::borrow::Cow;

use super::{FluidBackend, Role};
use crate::dataset::fluid::{FluidTracking, base_fluid_name};
use crate::scene_api::{
    ApiError, DynamicsBackend, EventAction, ObjectId, SceneEvent, SceneObjectInfo, Target, misuse,
    unknown_action,
};

/// The run an event starts.
pub(super) struct Run<'a> {
    /// Its tracking data: recorded in the annotation, or simulated (`--dynamics simulate`).
    tracking: Cow<'a, FluidTracking>,
    /// The stick removed in it (a counterfactual run).
    removed: Option<&'a SceneObjectInfo>,
    /// The tracking key of the fluid an `emit` event emits (`Later Emitted Yellow Fluid`).
    emitted: Option<&'a str>,
}

impl Run<'_> {
    /// The run in messages: `the factual run`, `the run without the brown stick`.
    fn describe(&self) -> String {
        match self.removed {
            Some(stick) => format!("the run without the {}", stick.describe()),
            None => "the factual run".to_string(),
        }
    }
}

/// What `happen` asks about a fluid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
    /// It passes a stick (touches it with more than 20 particles).
    Pass,
    /// It enters a container (more than 20 particles end in it).
    Enter,
    /// Most of it enters a container: strictly more than in every other container.
    EnterMost,
}

impl Outcome {
    /// Reads `happen`'s action (lower case, trimmed).
    fn parse(action: &str) -> Result<Outcome, ApiError> {
        match action {
            "passing" | "pass" | "passes" => Ok(Outcome::Pass),
            "entering" | "enter" | "enters" | "flowing into" | "flow into" => Ok(Outcome::Enter),
            "entering most" | "enter most" | "most entering" | "mostly entering"
            | "entering mostly" => Ok(Outcome::EnterMost),
            "motion" | "move" | "moving" | "rotation" | "rotate" | "rotating" | "collision"
            | "falling" | "touching" | "droping" | "dropping" => Err(misuse(format!(
                "happen: `{action}` belongs to other scenarios; fluid scenes answer 'passing' (a stick), 'entering' and 'entering most' (a container)"
            ))),
            _ => Err(unknown_action(
                action,
                "fluid",
                "passing, entering, entering most",
            )),
        }
    }

    /// The action as messages quote it.
    fn word(self) -> &'static str {
        match self {
            Outcome::Pass => "passing",
            Outcome::Enter => "entering",
            Outcome::EnterMost => "entering most",
        }
    }

    /// The kind of its target.
    fn target_kind(self) -> &'static str {
        match self {
            Outcome::Pass => "stick",
            Outcome::Enter | Outcome::EnterMost => "container",
        }
    }
}

/// The message for events fluid scenes do not have.
fn event_misuse() -> ApiError {
    misuse(
        "register_event: fluid scenes support register_event([], 'remove', 'green stick') (or the stick as the object), \
         register_event(emitter, 'emit', 'fluid') and register_event([], 'simulate', ''); 'increase' and 'decrease' change masses in rope scenes",
    )
}

/// How an event of `action` names its object, for messages.
fn event_usage(action: EventAction) -> &'static str {
    match action {
        EventAction::Emit => {
            "register_event(fluid_scene.find('other yellow emitter'), 'emit', 'fluid')"
        }
        _ => {
            "register_event([], 'remove', 'green stick') or register_event(fluid_scene.find('green stick'), 'remove', 'stick')"
        }
    }
}

impl FluidBackend {
    /// The run `event` starts; `function` names the call in messages. Misuse is reported
    /// first, then `--dynamics simulate`, then a run the video lacks.
    pub(super) fn event_run(
        &self,
        event: &SceneEvent,
        function: &str,
    ) -> Result<Run<'_>, ApiError> {
        let run = match event.action {
            EventAction::Simulate => Run {
                tracking: self.run_tracking(None, function)?,
                removed: None,
                emitted: None,
            },
            EventAction::Emit => {
                let emitter = self.event_object(event, "emitter", function)?;
                let Some(Role::Emitter { fluid, .. }) = self.role(emitter) else {
                    return Err(misuse(format!(
                        "{function}: the {} is not an emitter",
                        emitter.describe()
                    )));
                };
                Run {
                    tracking: self.run_tracking(None, function)?,
                    removed: None,
                    emitted: Some(fluid.as_str()),
                }
            }
            EventAction::Remove => {
                let stick = self.event_object(event, "stick", function)?;
                Run {
                    tracking: self.run_tracking(Some(stick), function)?,
                    removed: Some(stick),
                    emitted: None,
                }
            }
            EventAction::Increase | EventAction::Decrease => return Err(event_misuse()),
        };
        Ok(run)
    }

    /// The tracking data of the factual run, or of the run without `removed`: recorded in the
    /// annotation (`--dynamics annotation`, which has counterfactual runs for a few sticks
    /// only) or simulated on first use (`--dynamics simulate`, any stick).
    fn run_tracking(
        &self,
        removed: Option<&SceneObjectInfo>,
        function: &str,
    ) -> Result<Cow<'_, FluidTracking>, ApiError> {
        if self.dynamics == DynamicsBackend::Simulate {
            let runs = self.simulated_runs()?;
            return runs
                .run(removed.map(|stick| stick.name.as_str()))
                .map(Cow::Owned);
        }
        let Some(stick) = removed else {
            return Ok(Cow::Borrowed(&self.annotation.tracking));
        };
        self.annotation
            .counterfactual_without(&stick.name)
            .map(|record| Cow::Borrowed(&record.tracking))
            .ok_or_else(|| {
                let removable: Vec<String> = self
                    .annotation
                    .counterfactuals
                    .iter()
                    .map(|run| run.removed_stick.to_lowercase())
                    .collect();
                ApiError::Unavailable(format!(
                    "{function}: this video has no counterfactual run without the {} (its runs remove: {})",
                    stick.describe(),
                    if removable.is_empty() {
                        "none".to_string()
                    } else {
                        removable.join(", ")
                    }
                ))
            })
    }

    /// The one object of `kind` an `emit` or `remove` event acts on: its object, or what its
    /// attribute names (objects, or a description read with `find`'s words).
    fn event_object(
        &self,
        event: &SceneEvent,
        kind: &str,
        function: &str,
    ) -> Result<&SceneObjectInfo, ApiError> {
        let action = if event.action == EventAction::Emit {
            "emit"
        } else {
            "remove"
        };
        let usage = event_usage(event.action);
        let attribute = event.attribute.as_str();
        let plain = attribute.is_empty() || attribute == kind || attribute == "fluid";
        let described: Option<Vec<ObjectId>> = if !event.attribute_objects.is_empty() {
            Some(event.attribute_objects.clone())
        } else if plain {
            None
        } else {
            Some(self.resolve(attribute, function)?)
        };
        let chosen = match (event.object, described) {
            (Some(object), None) => vec![object],
            (Some(object), Some(named)) if named == [object] => vec![object],
            (Some(_), Some(_)) => {
                return Err(misuse(format!(
                    "{function}: '{action}' names its {kind} once, as the object or as the attribute, e.g. {usage}"
                )));
            }
            (None, Some(named)) => named,
            (None, None) => {
                return Err(self.named_nothing(format!(
                    "{function}: '{action}' needs the {kind} (got none; an empty list from `find` names none), e.g. {usage}"
                )));
            }
        };
        let objects = chosen
            .iter()
            .map(|id| self.info(*id, function))
            .collect::<Result<Vec<_>, _>>()?;
        let of_kind: Vec<&SceneObjectInfo> = objects
            .iter()
            .copied()
            .filter(|object| object.kind == kind)
            .collect();
        match (objects.as_slice(), of_kind.as_slice()) {
            (_, [one]) => Ok(one),
            ([], _) => Err(self.named_nothing(format!(
                "{function}: `{attribute}` names no object of this scene; {}",
                self.names_of_kind(kind)
            ))),
            ([other], []) => Err(misuse(match event.action {
                EventAction::Emit => format!(
                    "{function}: 'emit' takes an emitter, not the {}, e.g. {usage}",
                    other.describe()
                ),
                _ => format!(
                    "{function}: only sticks can be removed in fluid scenes, not the {}",
                    other.describe()
                ),
            })),
            (many, _) => {
                let names: Vec<String> = many.iter().map(|o| o.describe()).collect();
                Err(misuse(format!(
                    "{function}: '{action}' takes one {kind}, but `{}` names {} objects ({})",
                    if attribute.is_empty() {
                        "the attribute"
                    } else {
                        attribute
                    },
                    many.len(),
                    names.join(", ")
                )))
            }
        }
    }

    /// `happen`: whether `subject`'s fluid does `action` to `target` in the run of `event`.
    pub(super) fn happens(
        &self,
        event: &SceneEvent,
        subject: ObjectId,
        action: &str,
        target: &Target,
    ) -> Result<bool, ApiError> {
        let subject = self.info(subject, "happen")?;
        let outcome = Outcome::parse(action)?;
        if !matches!(self.role(subject), Some(Role::Fluid | Role::Emitter { .. })) {
            return Err(misuse(format!(
                "happen: only fluids flow in fluid scenes; ask about a fluid or an emitter (its fluid), not the {}",
                subject.describe()
            )));
        }
        let target = self.happen_target(target, outcome)?;
        let run = self.event_run(event, "happen")?;
        let fluid = self.fluid_key(subject, &run)?;
        let tracking = &run.tracking;
        match outcome {
            Outcome::Pass => {
                // A removed stick is passed by nothing.
                if run.removed.is_some_and(|stick| stick.id == target.id) {
                    return Ok(false);
                }
                let contacts = tracking.contacts(fluid).ok_or_else(|| {
                    ApiError::Unavailable(format!(
                        "happen: {} records no sticks the fluid of the {} touched",
                        run.describe(),
                        subject.describe()
                    ))
                })?;
                Ok(contacts.contains_key(&target.name))
            }
            Outcome::Enter => Ok(tracking.particles_in(&target.name, fluid) > 0),
            Outcome::EnterMost => Ok(tracking.holds_most(&target.name, fluid)),
        }
    }

    /// The one stick or container `happen` asks about.
    fn happen_target(
        &self,
        target: &Target,
        outcome: Outcome,
    ) -> Result<&SceneObjectInfo, ApiError> {
        let (action, kind) = (outcome.word(), outcome.target_kind());
        let ids = match target {
            Target::Objects(ids) => ids.clone(),
            Target::Text(text) if text.trim().is_empty() => {
                return Err(misuse(format!(
                    "happen: '{action}' needs the {kind}, e.g. happen([fluid], '{action}', [{kind}])"
                )));
            }
            Target::Text(text) => self.resolve(text, "happen")?,
        };
        match ids.as_slice() {
            [one] => {
                let object = self.info(*one, "happen")?;
                if object.kind == kind {
                    Ok(object)
                } else {
                    Err(misuse(format!(
                        "happen: '{action}' takes a {kind}, not the {}",
                        object.describe()
                    )))
                }
            }
            [] => Err(self.named_nothing(format!(
                "happen: the target of '{action}' names no {kind} (an empty list: `find` found no such object); {}",
                self.names_of_kind(kind)
            ))),
            many => Err(misuse(format!(
                "happen: ask about one {kind} at a time, got {} objects",
                many.len()
            ))),
        }
    }

    /// The tracking key of the fluid `subject` stands for in `run`: a fluid is itself, or, in
    /// an `emit` run, the emitted fluid of its colour; an emitter is the fluid it emits.
    fn fluid_key<'a>(
        &'a self,
        subject: &'a SceneObjectInfo,
        run: &Run<'a>,
    ) -> Result<&'a str, ApiError> {
        match self.role(subject) {
            Some(Role::Emitter { fluid, later }) => {
                if *later && run.removed.is_some() {
                    return Err(ApiError::Unavailable(format!(
                        "happen: counterfactual runs start the first emitters only; the {} does not emit in {}",
                        subject.describe(),
                        run.describe()
                    )));
                }
                Ok(fluid.as_str())
            }
            _ => Ok(match run.emitted {
                Some(emitted) if base_fluid_name(emitted) == subject.name => emitted,
                _ => subject.name.as_str(),
            }),
        }
    }
}

//! The scene API as Python: `SoftScene`, `SceneObject`, `SceneEvent`, `SoftDynamicScene`, the
//! global `video`, `bool_to_yesno`, `query_both` and the exception class `SceneApiError`, with
//! the paper's signatures (listing `tb:oracle_prompt`), bound to a Rust [`Scene`].
//!
//! Every call validates its arguments here and in `scene_api`; misuse raises `SceneApiError`
//! with a message that tells the program's author what is allowed. Object arguments accept a
//! `SceneObject`, a list of them, or the list `find` returned, nested as in the paper's listings
//! (`happen([pink_fluid], ...)`). Time inside calls is measured apart from the program's own time.

use std::cell::RefCell;
use std::sync::Arc;

use rustpython_vm::builtins::{PyBaseExceptionRef, PyType, PyTypeRef};
use rustpython_vm::class::PyClassImpl;
use rustpython_vm::{PyPayload, PyResult, VirtualMachine};

mod arguments;
mod classes;

use self::classes::{
    SceneEventObject, SceneObject, SoftDynamicScene, SoftScene, Video, bool_to_yesno, query_both,
};
use super::{ApiClock, Host, HostConfigError, HostRegistry, HostSpec, InstallContext};
use crate::scenarios;
use crate::scene_api::{ApiError, PerceptionBackend, Scene, VideoSpec, WorkCounters};

/// The name the scene host is registered under in sandbox workers.
pub const SCENE_HOST_NAME: &str = "scene";

/// The host spec of a video's scene (its config is the [`VideoSpec`] as JSON).
pub fn scene_host_spec(video: &VideoSpec) -> HostSpec {
    HostSpec {
        name: SCENE_HOST_NAME.to_string(),
        config: serde_json::to_value(video).unwrap_or(serde_json::Value::Null),
    }
}

/// The scene API host: one per video in a worker (the registry memoises it), so the video's
/// annotations are loaded once and every program on that video reuses them.
#[derive(Debug)]
pub struct SceneHost {
    scene: Arc<Scene>,
    /// Work already reported, so each unit reports only its own.
    reported: WorkCounters,
}

impl SceneHost {
    /// A host for `video`; nothing is read until a program asks.
    pub fn new(video: VideoSpec) -> SceneHost {
        let parts = scenarios::scene_parts(video.scenario);
        SceneHost {
            scene: Arc::new(Scene::open(video, parts)),
            reported: WorkCounters::default(),
        }
    }

    /// Builds a host from its spec's JSON config.
    pub fn from_config(config: &serde_json::Value) -> Result<SceneHost, HostConfigError> {
        let video: VideoSpec = serde_json::from_value(config.clone())
            .map_err(|error| HostConfigError(format!("bad scene host config: {error}")))?;
        Ok(SceneHost::new(video))
    }

    /// Registers the scene host in a worker's registry.
    pub fn register(registry: &mut HostRegistry) {
        registry.register(SCENE_HOST_NAME, |config| {
            SceneHost::from_config(config).map(|host| Box::new(host) as Box<dyn Host>)
        });
    }
}

/// Exception classes: `SceneApiError` (misuse), and its subclasses for calls the video cannot
/// answer (among them objects perception did not see) and for broken video files. Their names
/// tell the pipeline the failure's kind. Each row: kind, class name, index of the base class.
const ERROR_CLASSES: [(&str, &str, usize); 4] = [
    ("misuse", "SceneApiError", 0),
    ("unavailable", "SceneUnavailableError", 0),
    ("data", "SceneDataError", 0),
    ("not_seen", "SceneNotSeenError", 1),
];

/// The failure kind of an uncaught scene exception class.
pub fn scene_error_kind(class_name: &str) -> Option<&'static str> {
    ERROR_CLASSES
        .iter()
        .find(|(_, name, _)| *name == class_name)
        .map(|(kind, _, _)| *kind)
}

impl Host for SceneHost {
    fn install(&mut self, context: &mut InstallContext<'_>) -> PyResult<()> {
        let base = context.cached("scene/SceneApiError", |vm| {
            Ok(vm
                .ctx
                .new_exception_type("scene", "SceneApiError", None)
                .into())
        })?;
        let base_type = base
            .clone()
            .downcast::<PyType>()
            .map_err(|_| context.vm.new_runtime_error("SceneApiError is not a class"))?;
        let mut classes = vec![("misuse", base_type)];
        for (kind, name, parent) in &ERROR_CLASSES[1..] {
            let base_type = classes
                .get(*parent)
                .map(|(_, class)| class.clone())
                .ok_or_else(|| {
                    context
                        .vm
                        .new_runtime_error("scene error base is not defined")
                })?;
            let class = context.cached(&format!("scene/{name}"), move |vm| {
                Ok(vm
                    .ctx
                    .new_exception_type("scene", name, Some(vec![base_type]))
                    .into())
            })?;
            let class = class
                .downcast::<PyType>()
                .map_err(|_| context.vm.new_runtime_error("scene error is not a class"))?;
            classes.push((kind, class));
        }
        let vm = context.vm;
        for (_, class) in &classes {
            context.set_global(class.name().as_ref(), class.clone().into())?;
        }
        context.set_global("SoftScene", SoftScene::make_static_type().into())?;
        context.set_global("SceneObject", SceneObject::make_static_type().into())?;
        context.set_global("SceneEvent", SceneEventObject::make_static_type().into())?;
        context.set_global(
            "SoftDynamicScene",
            SoftDynamicScene::make_static_type().into(),
        )?;
        let _ = Video::make_static_type();
        context.set_global(
            "video",
            Video {
                scene: Arc::clone(&self.scene),
            }
            .into_ref(&vm.ctx)
            .into(),
        )?;
        let clock = context.clock.clone();
        let yesno = context.cached("scene/bool_to_yesno", |vm| {
            Ok(vm.new_function("bool_to_yesno", bool_to_yesno).into())
        })?;
        context.set_global("bool_to_yesno", yesno)?;
        let both = context.cached("scene/query_both", |vm| {
            Ok(vm.new_function("query_both", query_both).into())
        })?;
        context.set_global("query_both", both)?;
        BINDING.with(|binding| {
            *binding.borrow_mut() = Some(Binding {
                scene: Arc::clone(&self.scene),
                clock,
                classes,
            });
        });
        Ok(())
    }

    fn take_work_counters(&mut self) -> serde_json::Value {
        let now = self.scene.work();
        let delta = now.since(&self.reported);
        self.reported = now;
        serde_json::to_value(delta).unwrap_or(serde_json::Value::Null)
    }

    fn api_error_class(&self) -> Option<&str> {
        Some("SceneApiError")
    }
}

/// The binding state of the program running on this thread (set by [`SceneHost::install`]).
pub(super) struct Binding {
    scene: Arc<Scene>,
    clock: ApiClock,
    classes: Vec<(&'static str, PyTypeRef)>,
}

thread_local! {
    static BINDING: RefCell<Option<Binding>> = const { RefCell::new(None) };
}

/// Runs a scene-API call through the sandbox's clock (its time is API time, and a Rust panic in
/// it fails only this program) and turns an `ApiError` into the matching scene exception.
pub(super) fn api_call<T>(
    vm: &VirtualMachine,
    scene: &Scene,
    call: impl FnOnce(&Scene) -> Result<T, ApiError>,
) -> PyResult<T> {
    let clock = BINDING
        .with(|b| b.borrow().as_ref().map(|b| b.clock.clone()))
        .ok_or_else(|| vm.new_runtime_error("the scene API is not bound in this interpreter"))?;
    clock.call(vm, || {
        call(scene).map_err(|error| api_error(vm, error.kind(), &error.to_string()))
    })
}

/// A scene exception of `kind` with `message`.
pub(super) fn api_error(vm: &VirtualMachine, kind: &str, message: &str) -> PyBaseExceptionRef {
    let class = BINDING.with(|b| {
        b.borrow().as_ref().and_then(|b| {
            b.classes
                .iter()
                .find(|(k, _)| *k == kind)
                .or_else(|| b.classes.first())
                .map(|(_, c)| c.clone())
        })
    });
    match class {
        Some(class) => vm.new_exception_msg(class, message.into()),
        None => vm.new_runtime_error(message.to_string()),
    }
}

pub(super) fn misuse(vm: &VirtualMachine, message: &str) -> PyBaseExceptionRef {
    api_error(vm, "misuse", message)
}

/// The error for an empty list where one object is needed: `find` found nothing. Under
/// perception from pixels that may be a perception miss (`not_seen`), as the scene's own calls
/// decide ([`crate::scene_api::named_nothing`]); otherwise it is misuse.
pub(super) fn empty_list_error(vm: &VirtualMachine, message: String) -> PyBaseExceptionRef {
    let from_pixels = BINDING.with(|b| {
        b.borrow()
            .as_ref()
            .is_some_and(|b| b.scene.spec().perception != PerceptionBackend::Annotation)
    });
    let error = crate::scene_api::named_nothing(message, from_pixels);
    api_error(vm, error.kind(), &error.to_string())
}

#[cfg(test)]
mod tests {
    //! The bindings on the real rope video, in a plain (unlocked) interpreter; the sandbox's own
    //! tests cover the locked-down worker path.
    use super::*;
    use crate::dataset::{Scenario, VideoFolder, VideoId};
    use crate::sandbox::{Budgets, Error, Sandbox};
    use crate::scene_api::{DynamicsBackend, PerceptionBackend};

    fn run(source: &str) -> Result<String, String> {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/pulley_group/0");
        let video = VideoFolder {
            scenario: Scenario::Rope,
            id: VideoId("0".into()),
            dir,
        };
        let mut host = SceneHost::new(VideoSpec::new(
            &video,
            PerceptionBackend::Annotation,
            DynamicsBackend::Annotation,
        ));
        let mut sandbox = Sandbox::new();
        let report = sandbox.run(&mut host, source, &Budgets::default());
        match report.outcome {
            Ok(value) => Ok(value.to_plain_json().to_string()),
            Err(Error::ApiException {
                class_name,
                message,
                ..
            }) => Err(format!(
                "{class_name}[{}]: {message}",
                scene_error_kind(&class_name).unwrap_or("-")
            )),
            Err(other) => Err(format!("{}: {other}", other.kind())),
        }
    }

    #[test]
    fn paper_listing_eg1_runs_on_the_real_video() {
        let program = r#"
def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    green_cube = rope_scene.find("green cube")
    purple_cube = rope_scene.find("purple cube")
    green_cube_mass = rope_scene.query_single('mass', green_cube[0])
    purple_cube_mass = rope_scene.query_single('mass', purple_cube[0])
    if green_cube_mass is not None and purple_cube_mass is not None:
        return bool_to_yesno(green_cube_mass > 0.5 * purple_cube_mass)
    else:
        return "can not answer"
answer = execute_command(video)
"#;
        assert_eq!(run(program).unwrap(), "\"yes\"");
    }

    #[test]
    fn objects_events_and_dynamic_scenes_behave_as_documented() {
        let cases = [
            (
                "s = SoftScene(video, 'rope')\nanswer = [o.name for o in s.find('pulley')]",
                "[\"blue solid pulley\",\"gray hollow pulley\",\"pink solid pulley\",\"purple solid pulley\"]",
            ),
            (
                "s = SoftScene(video, 'rope')\nanswer = s.query_pair('mass', s.find('purple cube'), s.find('green cube'))",
                "[0.2,0.25]",
            ),
            (
                "s = SoftScene(video, 'rope')\nanswer = query_both('mass', s.find('purple cube'), s.find('pink sphere'))",
                "[null,null]",
            ),
            (
                "s = SoftScene(video, 'rope', mode='offline', video_id='0')\ne = s.register_event(s.find('purple cube'), 'decrease', 'mass')\nd = s.init_dyn_simulation(e)\nanswer = (d.happen([s.find('purple cube')], 'motion', 'up'), d.happen(s.find('blue pulley'), 'rotation', 'clockwise'))",
                "[true,true]",
            ),
            (
                "s = SoftScene(video, 'rope')\nd = s.init_dyn_simulation(s.event([], 'simulate', ''))\nanswer = bool_to_yesno(d.happen(s.find('green cube'), 'motion', 'down'))",
                "\"yes\"",
            ),
            (
                "s = SoftScene(video, 'rope')\nanswer = s.find('cube')[0] == s.find('purple')[0], len({o for o in s.find('cube') + s.find('cube')})",
                "[true,2]",
            ),
            (
                "s = SoftScene(video, 'rope')\np = s.find('gray pulley')[0]\nc = s.find('purple cube')[0]\nanswer = (p.shape, p.dynamic, p.kind, p.type, c.shape, c.dynamic, c.color, p.full_name)",
                "[\"hollow\",\"static\",\"pulley\",\"pulley\",null,\"dynamic\",\"purple\",\"Gray Hollow Static Pulley (0 2)\"]",
            ),
            (
                "s = SoftScene(video, 'rope')\ntry:\n    s.find('gray pulley')[0].grid\nexcept AttributeError:\n    answer = 'no grid attribute'",
                "\"no grid attribute\"",
            ),
            (
                "answer = repr(SoftScene(video, 'rope').find('brown fixed point')[0])",
                "\"SceneObject('brown fixed point')\"",
            ),
            (
                "s = SoftScene(video, 'rope')\ntry:\n    s.find('banana')\nexcept SceneApiError as e:\n    answer = 'caught'",
                "\"caught\"",
            ),
            (
                // A perception miss is a kind of unavailability: a program that catches
                // `SceneUnavailableError` (as the API spec describes) catches it too.
                "answer = [issubclass(SceneNotSeenError, SceneUnavailableError), issubclass(SceneUnavailableError, SceneApiError), issubclass(SceneDataError, SceneUnavailableError)]",
                "[true,true,false]",
            ),
        ];
        for (program, expected) in cases {
            assert_eq!(run(program).as_deref(), Ok(expected), "{program}");
        }
    }

    #[test]
    fn misuse_raises_scene_api_error_with_guidance() {
        let cases = [
            (
                "SoftScene(video, 'fluid')",
                "misuse",
                "this video is a rope scene, not `fluid`",
            ),
            (
                "SoftScene(video)",
                "misuse",
                "SoftScene() is missing `scene_name`",
            ),
            (
                "SoftScene(42, 'rope')",
                "misuse",
                "`video` must be the video given to execute_command, got int",
            ),
            (
                "SoftScene(video, 'rope', colour='red')",
                "misuse",
                "has no parameter `colour`",
            ),
            (
                "s = SoftScene(video, 'rope')\ns.query_pair('mass', s.find('cube'), s.find('pink sphere'))",
                "misuse",
                "`object1` holds 2 objects",
            ),
            (
                "s = SoftScene(video, 'rope')\ns.query_single('mass', s.find('red cube'))",
                "misuse",
                "`object` is an empty list",
            ),
            (
                "s = SoftScene(video, 'rope')\ns.query_single('mass', 'purple cube')",
                "misuse",
                "must be a SceneObject or a list of them",
            ),
            (
                "s = SoftScene(video, 'rope')\ns.init_dyn_simulation('go')",
                "misuse",
                "expected the SceneEvent that register_event returned",
            ),
            (
                "s = SoftScene(video, 'rope')\nd = s.init_dyn_simulation(s.register_event([], 'simulate', ''))\nd.happen(s.find('purple cube'), 'flying', 'up')",
                "misuse",
                "unknown action `flying`",
            ),
            (
                "s = SoftScene(video, 'rope')\nd = s.init_dyn_simulation(s.register_event([], 'simulate', ''))\nd.final_pose(s.find('purple cube'))",
                "misuse",
                "final_pose: the objects of rope scenes have no final pose to ask about; use happen",
            ),
            (
                "s = SoftScene(video, 'rope')\nd = s.init_dyn_simulation(s.register_event([], 'simulate', ''))\nd.final_pose(s.find('cube'))",
                "misuse",
                "final_pose: `scene_object` holds 2 objects",
            ),
            (
                // The paper's listing eg3 passes both objects of a relation.
                "s = SoftScene(video, 'rope')\nd = s.init_dyn_simulation(s.register_event([], 'simulate', ''))\nd.happen([s.find('purple cube'), s.find('green cube')], 'touching', '')",
                "misuse",
                "got 2; e.g. happen([cube], 'motion', 'up'); a relation between two objects names the second as the target: happen([a], 'touching', [b])",
            ),
            ("SceneObject()", "misuse", "use scene.find(name)"),
        ];
        for (program, kind, expected) in cases {
            let error = run(program).unwrap_err();
            assert!(
                error.starts_with(&format!("SceneApiError[{kind}]")),
                "{program}: {error}"
            );
            assert!(
                error.contains(expected),
                "{program}: `{error}` lacks `{expected}`"
            );
        }
    }
}

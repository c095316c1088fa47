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

use rustpython_vm::builtins::{PyBaseExceptionRef, PyList, PyStr, PyTuple, PyType, PyTypeRef};
use rustpython_vm::class::PyClassImpl;
use rustpython_vm::function::FuncArgs;
use rustpython_vm::types::{
    Comparable, Constructor, GetAttr, Hashable, PyComparisonOp, Representable,
};
use rustpython_vm::{
    AsObject, Py, PyObject, PyObjectRef, PyPayload, PyResult, VirtualMachine, pyclass,
};

use super::{ApiClock, Host, HostConfigError, HostRegistry, HostSpec, InstallContext};
use crate::dataset::Scenario;
use crate::scenarios;
use crate::scene_api::{
    ApiError, ObjectId, Scene, SceneEvent as RustEvent, SceneObjectInfo, Target, VideoSpec,
    WorkCounters,
};

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
/// answer and for broken video files. Their names tell the pipeline the failure's kind.
const ERROR_CLASSES: [(&str, &str); 3] = [
    ("misuse", "SceneApiError"),
    ("unavailable", "SceneUnavailableError"),
    ("data", "SceneDataError"),
];

/// The failure kind of an uncaught scene exception class.
pub fn scene_error_kind(class_name: &str) -> Option<&'static str> {
    ERROR_CLASSES
        .iter()
        .find(|(_, name)| *name == class_name)
        .map(|(kind, _)| *kind)
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
        let mut classes = vec![("misuse", base_type.clone())];
        for (kind, name) in &ERROR_CLASSES[1..] {
            let base_type = base_type.clone();
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
struct Binding {
    scene: Arc<Scene>,
    clock: ApiClock,
    classes: Vec<(&'static str, PyTypeRef)>,
}

thread_local! {
    static BINDING: RefCell<Option<Binding>> = const { RefCell::new(None) };
}

/// Runs a scene-API call through the sandbox's clock (its time is API time, and a Rust panic in
/// it fails only this program) and turns an `ApiError` into the matching scene exception.
fn api_call<T>(
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
fn api_error(vm: &VirtualMachine, kind: &str, message: &str) -> PyBaseExceptionRef {
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

fn misuse(vm: &VirtualMachine, message: &str) -> PyBaseExceptionRef {
    api_error(vm, "misuse", message)
}

/// A short description of a Python value's type for messages.
fn type_name(object: &PyObject) -> String {
    object.class().name().to_string()
}

/// Flattens an object argument: a `SceneObject`, or lists/tuples of them nested up to 4 deep.
fn collect_objects(
    vm: &VirtualMachine,
    value: &PyObject,
    function: &str,
    parameter: &str,
    depth: usize,
    out: &mut Vec<ObjectId>,
) -> PyResult<()> {
    if let Some(object) = value.downcast_ref::<SceneObject>() {
        out.push(object.info.id);
        return Ok(());
    }
    let items: Option<Vec<PyObjectRef>> = if let Some(list) = value.downcast_ref::<PyList>() {
        Some(list.borrow_vec().to_vec())
    } else {
        value
            .downcast_ref::<PyTuple>()
            .map(|tuple| tuple.as_slice().to_vec())
    };
    match items {
        Some(items) if depth < 4 => {
            for item in items {
                collect_objects(vm, &item, function, parameter, depth + 1, out)?;
            }
            Ok(())
        }
        Some(_) => Err(misuse(
            vm,
            &format!(
                "{function}: `{parameter}` is nested too deeply; pass a SceneObject or a list of them"
            ),
        )),
        None => Err(misuse(
            vm,
            &format!(
                "{function}: `{parameter}` must be a SceneObject or a list of them (as find returns), got {}",
                type_name(value)
            ),
        )),
    }
}

fn objects_argument(
    vm: &VirtualMachine,
    value: &PyObject,
    function: &str,
    parameter: &str,
) -> PyResult<Vec<ObjectId>> {
    let mut out = Vec::new();
    collect_objects(vm, value, function, parameter, 0, &mut out)?;
    Ok(out)
}

/// Exactly one object (a `SceneObject`, or a list holding one, as `find` returns).
fn one_object(
    vm: &VirtualMachine,
    value: &PyObject,
    function: &str,
    parameter: &str,
) -> PyResult<ObjectId> {
    let objects = objects_argument(vm, value, function, parameter)?;
    match objects.as_slice() {
        [one] => Ok(*one),
        [] => Err(misuse(
            vm,
            &format!("{function}: `{parameter}` is an empty list: `find` found no such object"),
        )),
        many => Err(misuse(
            vm,
            &format!(
                "{function}: `{parameter}` holds {} objects; pass one (e.g. `objects[0]`)",
                many.len()
            ),
        )),
    }
}

fn string_argument(
    vm: &VirtualMachine,
    value: &PyObject,
    function: &str,
    parameter: &str,
) -> PyResult<String> {
    value
        .downcast_ref::<PyStr>()
        .map(|s| s.to_string_lossy().into_owned())
        .ok_or_else(|| {
            misuse(
                vm,
                &format!(
                    "{function}: `{parameter}` must be a string, got {}",
                    type_name(value)
                ),
            )
        })
}

/// Binds positional and keyword arguments to `names`, erroring on unknown or missing ones.
fn bind_arguments(
    vm: &VirtualMachine,
    args: FuncArgs,
    function: &str,
    names: &[&str],
    required: usize,
) -> PyResult<Vec<Option<PyObjectRef>>> {
    if args.args.len() > names.len() {
        return Err(misuse(
            vm,
            &format!(
                "{function}() takes {} arguments ({}), got {}",
                names.len(),
                names.join(", "),
                args.args.len()
            ),
        ));
    }
    let mut bound: Vec<Option<PyObjectRef>> = args.args.into_iter().map(Some).collect();
    bound.resize(names.len(), None);
    for (key, value) in args.kwargs {
        let Some(index) = names.iter().position(|n| *n == key) else {
            return Err(misuse(
                vm,
                &format!(
                    "{function}() has no parameter `{key}`; parameters are {}",
                    names.join(", ")
                ),
            ));
        };
        if bound[index].is_some() {
            return Err(misuse(vm, &format!("{function}() got `{key}` twice")));
        }
        bound[index] = Some(value);
    }
    if let Some(missing) = names
        .iter()
        .take(required)
        .zip(&bound)
        .find(|(_, v)| v.is_none())
        .map(|(n, _)| n)
    {
        return Err(misuse(
            vm,
            &format!(
                "{function}() is missing `{missing}`; parameters are {}",
                names.join(", ")
            ),
        ));
    }
    Ok(bound)
}

fn string_list(vm: &VirtualMachine, items: &[&str]) -> PyObjectRef {
    vm.ctx
        .new_list(items.iter().map(|s| vm.ctx.new_str(*s).into()).collect())
        .into()
}

fn scene_object(vm: &VirtualMachine, info: SceneObjectInfo) -> PyObjectRef {
    SceneObject { info }.into_ref(&vm.ctx).into()
}

/// The video a program is given (`execute_command(video)`).
#[pyclass(module = "scene", name = "Video")]
#[derive(Debug, PyPayload)]
pub(crate) struct Video {
    scene: Arc<Scene>,
}

#[pyclass(with(Constructor, Representable))]
impl Video {
    #[pygetset]
    fn video_id(&self) -> String {
        self.scene.spec().video_id.clone()
    }

    #[pygetset]
    fn scene_name(&self) -> String {
        self.scene.spec().scenario.name().to_string()
    }
}

impl Constructor for Video {
    type Args = FuncArgs;

    fn py_new(_cls: &Py<PyType>, _args: FuncArgs, vm: &VirtualMachine) -> PyResult<Self> {
        Err(misuse(
            vm,
            "Video() cannot be created; use the `video` given to execute_command",
        ))
    }
}

impl Representable for Video {
    fn repr_str(zelf: &Py<Self>, _vm: &VirtualMachine) -> PyResult<String> {
        Ok(format!(
            "<video {}/{}>",
            zelf.scene.spec().scenario,
            zelf.scene.spec().video_id
        ))
    }
}

/// An object of the scene, as `find` returns it.
#[pyclass(module = "scene", name = "SceneObject")]
#[derive(Debug, PyPayload)]
pub(crate) struct SceneObject {
    info: SceneObjectInfo,
}

#[pyclass(with(Constructor, Representable, Comparable, Hashable, GetAttr))]
impl SceneObject {
    #[pygetset]
    fn name(&self) -> String {
        self.info.describe()
    }

    #[pygetset]
    fn full_name(&self) -> String {
        self.info.name.clone()
    }

    #[pygetset]
    fn color(&self) -> String {
        self.info.color.clone()
    }

    #[pygetset(name = "type")]
    fn kind_type(&self) -> String {
        self.info.kind.to_string()
    }

    #[pygetset]
    fn kind(&self) -> String {
        self.info.kind.to_string()
    }
}

/// The attributes of the object's scenario (rope: `shape`, `dynamic`) read as Python
/// attributes: the object's value, or `None` when it has none. Every other name is looked up as
/// usual.
impl GetAttr for SceneObject {
    fn getattro(zelf: &Py<Self>, name: &Py<PyStr>, vm: &VirtualMachine) -> PyResult {
        let key = name.to_string_lossy();
        if zelf.info.has_readable_attribute(&key) {
            return Ok(zelf
                .info
                .attribute(&key)
                .map_or_else(|| vm.ctx.none(), |value| vm.ctx.new_str(value).into()));
        }
        zelf.as_object().generic_getattr(name, vm)
    }
}

impl Constructor for SceneObject {
    type Args = FuncArgs;

    fn py_new(_cls: &Py<PyType>, _args: FuncArgs, vm: &VirtualMachine) -> PyResult<Self> {
        Err(misuse(
            vm,
            "SceneObject() cannot be created; use scene.find(name)",
        ))
    }
}

impl Representable for SceneObject {
    fn repr_str(zelf: &Py<Self>, _vm: &VirtualMachine) -> PyResult<String> {
        Ok(format!("SceneObject('{}')", zelf.info.describe()))
    }
}

impl Comparable for SceneObject {
    fn cmp(
        zelf: &Py<Self>,
        other: &PyObject,
        op: PyComparisonOp,
        _vm: &VirtualMachine,
    ) -> PyResult<rustpython_vm::function::PyComparisonValue> {
        let Some(other) = other.downcast_ref::<SceneObject>() else {
            return Ok(rustpython_vm::function::PyComparisonValue::NotImplemented);
        };
        op.eq_only(|| {
            Ok(rustpython_vm::function::PyComparisonValue::Implemented(
                zelf.info.id == other.info.id,
            ))
        })
    }
}

impl Hashable for SceneObject {
    fn hash(
        zelf: &Py<Self>,
        _vm: &VirtualMachine,
    ) -> PyResult<rustpython_vm::common::hash::PyHash> {
        Ok(rustpython_vm::common::hash::PyHash::from(zelf.info.id.0))
    }
}

/// `SoftScene(video, scene_name, start_frame=0, end_frame=-1, mode=None, video_id=None)`.
#[pyclass(module = "scene", name = "SoftScene")]
#[derive(Debug, PyPayload)]
pub(crate) struct SoftScene {
    scene: Arc<Scene>,
    mode: String,
    start_frame: i64,
    end_frame: i64,
}

const EVENT_ACTIONS: [&str; 5] = ["increase", "decrease", "emit", "remove", "simulate"];
const DYNAMIC_ACTIONS: [&str; 8] = [
    "entering",
    "passing",
    "motion",
    "rotation",
    "collision",
    "falling",
    "touching",
    "droping",
];

impl Constructor for SoftScene {
    type Args = FuncArgs;

    fn py_new(_cls: &Py<PyType>, args: FuncArgs, vm: &VirtualMachine) -> PyResult<Self> {
        let none = vm.ctx.none();
        let names = [
            "video",
            "scene_name",
            "start_frame",
            "end_frame",
            "mode",
            "video_id",
        ];
        let bound = bind_arguments(vm, args, "SoftScene", &names, 2)?;
        let video_arg = bound[0].clone().unwrap_or_else(|| vm.ctx.none());
        let video = video_arg.downcast_ref::<Video>().ok_or_else(|| {
            misuse(
                vm,
                &format!(
                    "SoftScene: `video` must be the video given to execute_command, got {}",
                    type_name(&video_arg)
                ),
            )
        })?;
        let scene = Arc::clone(&video.scene);
        let scene_name = string_argument(
            vm,
            bound[1].as_deref().unwrap_or(&none),
            "SoftScene",
            "scene_name",
        )?;
        let expected = scene.spec().scenario;
        if scene_name.trim().to_lowercase() != expected.name() {
            return Err(misuse(
                vm,
                &format!(
                    "SoftScene: this video is a {expected} scene, not `{scene_name}`; scene names are {}",
                    Scenario::names()
                ),
            ));
        }
        let integer = |value: &Option<PyObjectRef>, name: &str, default: i64| -> PyResult<i64> {
            match value {
                None => Ok(default),
                Some(v) if vm.is_none(v) => Ok(default),
                Some(v) => v.try_to_value::<i64>(vm).map_err(|_| {
                    misuse(
                        vm,
                        &format!("SoftScene: `{name}` must be an integer frame index"),
                    )
                }),
            }
        };
        let start_frame = integer(&bound[2], "start_frame", 0)?;
        let end_frame = integer(&bound[3], "end_frame", -1)?;
        // Annotation data is pre-computed, so the default mode is the paper's offline mode.
        let mode = match &bound[4] {
            Some(v) if !vm.is_none(v) => {
                string_argument(vm, v, "SoftScene", "mode")?.to_lowercase()
            }
            _ => "offline".to_string(),
        };
        if mode != "offline" && mode != "online" {
            return Err(misuse(
                vm,
                &format!("SoftScene: `mode` is 'online' or 'offline', not `{mode}`"),
            ));
        }
        if let Some(v) = bound[5].as_ref().filter(|v| !vm.is_none(v)) {
            let video_id = v.str(vm)?.to_string_lossy().into_owned();
            if video_id != scene.spec().video_id {
                return Err(misuse(
                    vm,
                    &format!(
                        "SoftScene: `video_id` {video_id} is not this video's id ({})",
                        scene.spec().video_id
                    ),
                ));
            }
        }
        Ok(SoftScene {
            scene,
            mode,
            start_frame,
            end_frame,
        })
    }
}

impl Representable for SoftScene {
    fn repr_str(zelf: &Py<Self>, _vm: &VirtualMachine) -> PyResult<String> {
        Ok(format!(
            "SoftScene('{}', video_id='{}')",
            zelf.scene.spec().scenario,
            zelf.scene.spec().video_id
        ))
    }
}

#[pyclass(with(Constructor, Representable))]
impl SoftScene {
    #[pygetset]
    fn scene_name(&self) -> String {
        self.scene.spec().scenario.name().to_string()
    }

    #[pygetset]
    fn mode(&self) -> String {
        self.mode.clone()
    }

    #[pygetset]
    fn vid(&self) -> String {
        self.scene.spec().video_id.clone()
    }

    #[pygetset]
    fn start_frame(&self) -> i64 {
        self.start_frame
    }

    #[pygetset]
    fn end_frame(&self) -> i64 {
        self.end_frame
    }

    #[pygetset]
    #[expect(clippy::unused_self, reason = "a Python attribute of the instance")]
    fn all_event_actions(&self, vm: &VirtualMachine) -> PyObjectRef {
        string_list(vm, &EVENT_ACTIONS)
    }

    /// `find(object_name) -> list[SceneObject]`.
    #[pymethod]
    fn find(&self, args: FuncArgs, vm: &VirtualMachine) -> PyResult<Vec<PyObjectRef>> {
        let none = vm.ctx.none();
        let bound = bind_arguments(vm, args, "find", &["object_name"], 1)?;
        let name = string_argument(
            vm,
            bound[0].as_deref().unwrap_or(&none),
            "find",
            "object_name",
        )?;
        let found = api_call(vm, &self.scene, |scene| {
            let ids = scene.find(&name)?;
            ids.into_iter()
                .map(|id| scene.object(id).cloned())
                .collect::<Result<Vec<_>, _>>()
        })?;
        Ok(found
            .into_iter()
            .map(|info| scene_object(vm, info))
            .collect())
    }

    /// `query_single(property, object)`.
    #[pymethod]
    fn query_single(&self, args: FuncArgs, vm: &VirtualMachine) -> PyResult<Option<f64>> {
        let none = vm.ctx.none();
        let bound = bind_arguments(vm, args, "query_single", &["property", "object"], 2)?;
        let property = string_argument(
            vm,
            bound[0].as_deref().unwrap_or(&none),
            "query_single",
            "property",
        )?;
        let object = one_object(
            vm,
            bound[1].as_deref().unwrap_or(&none),
            "query_single",
            "object",
        )?;
        api_call(vm, &self.scene, |scene| {
            scene.query_single(&property, object)
        })
    }

    /// `query_pair(property, object1, object2) -> (value1, value2)`.
    #[pymethod]
    fn query_pair(
        &self,
        args: FuncArgs,
        vm: &VirtualMachine,
    ) -> PyResult<(Option<f64>, Option<f64>)> {
        query_pair_impl(&self.scene, args, vm, "query_pair")
    }

    /// `register_event(scene_objects, action, attribute) -> SceneEvent`.
    #[pymethod]
    fn register_event(&self, args: FuncArgs, vm: &VirtualMachine) -> PyResult<PyObjectRef> {
        register_event_impl(&self.scene, args, vm, "register_event")
    }

    /// The paper's examples also call `event(...)`; same as `register_event`.
    #[pymethod]
    fn event(&self, args: FuncArgs, vm: &VirtualMachine) -> PyResult<PyObjectRef> {
        register_event_impl(&self.scene, args, vm, "event")
    }

    /// `init_dyn_simulation(event) -> SoftDynamicScene`.
    #[pymethod]
    fn init_dyn_simulation(&self, args: FuncArgs, vm: &VirtualMachine) -> PyResult<PyObjectRef> {
        let bound = bind_arguments(vm, args, "init_dyn_simulation", &["dyn_init_event"], 1)?;
        let value = bound[0].clone().unwrap_or_else(|| vm.ctx.none());
        let event = value.downcast_ref::<SceneEventObject>().ok_or_else(|| {
            misuse(vm, &format!("init_dyn_simulation: expected the SceneEvent that register_event returned, got {}", type_name(&value)))
        })?;
        Ok(SoftDynamicScene {
            scene: Arc::clone(&self.scene),
            event: event.event.clone(),
        }
        .into_ref(&vm.ctx)
        .into())
    }
}

fn query_pair_impl(
    scene: &Scene,
    args: FuncArgs,
    vm: &VirtualMachine,
    function: &str,
) -> PyResult<(Option<f64>, Option<f64>)> {
    let bound = bind_arguments(vm, args, function, &["property", "object1", "object2"], 3)?;
    let none = vm.ctx.none();
    let property = string_argument(
        vm,
        bound[0].as_deref().unwrap_or(&none),
        function,
        "property",
    )?;
    let first = one_object(
        vm,
        bound[1].as_deref().unwrap_or(&none),
        function,
        "object1",
    )?;
    let second = one_object(
        vm,
        bound[2].as_deref().unwrap_or(&none),
        function,
        "object2",
    )?;
    api_call(vm, scene, |scene| {
        scene.query_pair(&property, first, second)
    })
}

fn register_event_impl(
    scene: &Scene,
    args: FuncArgs,
    vm: &VirtualMachine,
    function: &str,
) -> PyResult<PyObjectRef> {
    let bound = bind_arguments(
        vm,
        args,
        function,
        &["scene_objects", "action", "attribute"],
        2,
    )?;
    let none = vm.ctx.none();
    let objects = objects_argument(
        vm,
        bound[0].as_deref().unwrap_or(&none),
        function,
        "scene_objects",
    )?;
    let action = string_argument(vm, bound[1].as_deref().unwrap_or(&none), function, "action")?;
    let (attribute, attribute_objects) = match bound[2].as_ref() {
        None => (String::new(), Vec::new()),
        Some(v) if vm.is_none(v) => (String::new(), Vec::new()),
        Some(v) => match v.downcast_ref::<PyStr>() {
            Some(text) => (text.to_string_lossy().into_owned(), Vec::new()),
            None => (
                String::new(),
                objects_argument(vm, v, function, "attribute")?,
            ),
        },
    };
    let event = api_call(vm, scene, |scene| {
        scene.register_event(&objects, &action, &attribute, attribute_objects)
    })?;
    Ok(SceneEventObject { event }.into_ref(&vm.ctx).into())
}

/// An event registered on a scene.
#[pyclass(module = "scene", name = "SceneEvent")]
#[derive(Debug, PyPayload)]
pub(crate) struct SceneEventObject {
    event: RustEvent,
}

impl Constructor for SceneEventObject {
    type Args = FuncArgs;

    fn py_new(_cls: &Py<PyType>, _args: FuncArgs, vm: &VirtualMachine) -> PyResult<Self> {
        Err(misuse(
            vm,
            "SceneEvent() cannot be created; use scene.register_event(objects, action, attribute)",
        ))
    }
}

impl Representable for SceneEventObject {
    fn repr_str(zelf: &Py<Self>, _vm: &VirtualMachine) -> PyResult<String> {
        let action = serde_json::to_value(zelf.event.action)
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default();
        Ok(format!(
            "SceneEvent('{action}', '{}')",
            zelf.event.attribute
        ))
    }
}

#[pyclass(with(Constructor, Representable))]
impl SceneEventObject {}

/// The dynamic scene started by an event.
#[pyclass(module = "scene", name = "SoftDynamicScene")]
#[derive(Debug, PyPayload)]
pub(crate) struct SoftDynamicScene {
    scene: Arc<Scene>,
    event: RustEvent,
}

impl Constructor for SoftDynamicScene {
    type Args = FuncArgs;

    fn py_new(_cls: &Py<PyType>, _args: FuncArgs, vm: &VirtualMachine) -> PyResult<Self> {
        Err(misuse(
            vm,
            "SoftDynamicScene() cannot be created; use scene.init_dyn_simulation(event)",
        ))
    }
}

impl Representable for SoftDynamicScene {
    fn repr_str(zelf: &Py<Self>, _vm: &VirtualMachine) -> PyResult<String> {
        Ok(format!(
            "SoftDynamicScene('{}')",
            zelf.scene.spec().scenario
        ))
    }
}

#[pyclass(with(Constructor, Representable))]
impl SoftDynamicScene {
    #[pygetset]
    fn scene_name(&self) -> String {
        self.scene.spec().scenario.name().to_string()
    }

    #[pygetset]
    #[expect(clippy::unused_self, reason = "a Python attribute of the instance")]
    fn all_dyn_actions(&self, vm: &VirtualMachine) -> PyObjectRef {
        string_list(vm, &DYNAMIC_ACTIONS)
    }

    /// `happen(scene_objects, action, target) -> bool`.
    #[pymethod]
    fn happen(&self, args: FuncArgs, vm: &VirtualMachine) -> PyResult<bool> {
        let bound = bind_arguments(
            vm,
            args,
            "happen",
            &["scene_objects", "action", "target"],
            2,
        )?;
        let none = vm.ctx.none();
        let objects = objects_argument(
            vm,
            bound[0].as_deref().unwrap_or(&none),
            "happen",
            "scene_objects",
        )?;
        let action = string_argument(vm, bound[1].as_deref().unwrap_or(&none), "happen", "action")?;
        let target = match bound[2].as_ref() {
            None => Target::Text(String::new()),
            Some(v) if vm.is_none(v) => Target::Text(String::new()),
            Some(v) => match v.downcast_ref::<PyStr>() {
                Some(text) => Target::Text(text.to_string_lossy().into_owned()),
                None => Target::Objects(objects_argument(vm, v, "happen", "target")?),
            },
        };
        let event = self.event.clone();
        api_call(vm, &self.scene, |scene| {
            scene.happen(&event, &objects, &action, &target)
        })
    }
}

/// `bool_to_yesno(bool_answer) -> "yes" | "no"` (Python truthiness).
fn bool_to_yesno(value: PyObjectRef, vm: &VirtualMachine) -> PyResult<&'static str> {
    Ok(if value.try_to_bool(vm)? { "yes" } else { "no" })
}

/// `query_both(property, object1, object2)`: the paper's listing calls it without a scene; it is
/// `query_pair` on the program's video.
fn query_both(args: FuncArgs, vm: &VirtualMachine) -> PyResult<(Option<f64>, Option<f64>)> {
    let scene = BINDING
        .with(|b| b.borrow().as_ref().map(|b| Arc::clone(&b.scene)))
        .ok_or_else(|| vm.new_runtime_error("the scene API is not bound in this interpreter"))?;
    query_pair_impl(&scene, args, vm, "query_both")
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

//! The Python classes of the scene API: `Video`, `SceneObject`, `SoftScene`, `SceneEvent` and
//! `SoftDynamicScene`, and the functions `bool_to_yesno` and `query_both`.

use std::sync::Arc;

use rustpython_vm::builtins::{PyStr, PyType};
use rustpython_vm::function::FuncArgs;
use rustpython_vm::types::{
    Comparable, Constructor, GetAttr, Hashable, PyComparisonOp, Representable,
};
use rustpython_vm::{
    AsObject, Py, PyObject, PyObjectRef, PyPayload, PyResult, VirtualMachine, pyclass,
};

use super::arguments::{
    bind_arguments, objects_argument, one_object, scene_object, string_argument, string_list,
    type_name,
};
use super::{BINDING, api_call, misuse};
use crate::dataset::Scenario;
use crate::scene_api::{Scene, SceneEvent as RustEvent, SceneObjectInfo, Target};

/// The video a program is given (`execute_command(video)`).
#[pyclass(module = "scene", name = "Video")]
#[derive(Debug, PyPayload)]
pub(crate) struct Video {
    pub(super) scene: Arc<Scene>,
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
    pub(super) info: SceneObjectInfo,
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

    /// `final_pose(scene_object) -> str`: how the object ends, in the words of its scenario's
    /// pose questions.
    #[pymethod]
    fn final_pose(&self, args: FuncArgs, vm: &VirtualMachine) -> PyResult<String> {
        let bound = bind_arguments(vm, args, "final_pose", &["scene_object"], 1)?;
        let none = vm.ctx.none();
        let object = one_object(
            vm,
            bound[0].as_deref().unwrap_or(&none),
            "final_pose",
            "scene_object",
        )?;
        let event = self.event.clone();
        api_call(vm, &self.scene, |scene| scene.final_pose(&event, object))
    }
}

/// `bool_to_yesno(bool_answer) -> "yes" | "no"` (Python truthiness).
pub(super) fn bool_to_yesno(value: PyObjectRef, vm: &VirtualMachine) -> PyResult<&'static str> {
    Ok(if value.try_to_bool(vm)? { "yes" } else { "no" })
}

/// `query_both(property, object1, object2)`: the paper's listing calls it without a scene; it is
/// `query_pair` on the program's video.
pub(super) fn query_both(
    args: FuncArgs,
    vm: &VirtualMachine,
) -> PyResult<(Option<f64>, Option<f64>)> {
    let scene = BINDING
        .with(|b| b.borrow().as_ref().map(|b| Arc::clone(&b.scene)))
        .ok_or_else(|| vm.new_runtime_error("the scene API is not bound in this interpreter"))?;
    query_pair_impl(&scene, args, vm, "query_both")
}

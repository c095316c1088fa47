//! Reading a scene-API call's Python arguments: binding positional and keyword arguments to
//! parameter names, and turning values into objects and strings, with a `SceneApiError` that
//! says what was expected.

use rustpython_vm::builtins::{PyList, PyStr, PyTuple};
use rustpython_vm::function::FuncArgs;
use rustpython_vm::{PyObject, PyObjectRef, PyPayload, PyResult, VirtualMachine};

use super::classes::SceneObject;
use super::misuse;
use crate::scene_api::{ObjectId, SceneObjectInfo};

/// A short description of a Python value's type for messages.
pub(super) fn type_name(object: &PyObject) -> String {
    object.class().name().to_string()
}

/// Flattens an object argument: a `SceneObject`, or lists/tuples of them nested up to 4 deep.
pub(super) fn collect_objects(
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

pub(super) fn objects_argument(
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
pub(super) fn one_object(
    vm: &VirtualMachine,
    value: &PyObject,
    function: &str,
    parameter: &str,
) -> PyResult<ObjectId> {
    let objects = objects_argument(vm, value, function, parameter)?;
    match objects.as_slice() {
        [one] => Ok(*one),
        [] => Err(super::empty_list_error(
            vm,
            format!("{function}: `{parameter}` is an empty list: `find` found no such object"),
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

pub(super) fn string_argument(
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
pub(super) fn bind_arguments(
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

pub(super) fn string_list(vm: &VirtualMachine, items: &[&str]) -> PyObjectRef {
    vm.ctx
        .new_list(items.iter().map(|s| vm.ctx.new_str(*s).into()).collect())
        .into()
}

pub(super) fn scene_object(vm: &VirtualMachine, info: SceneObjectInfo) -> PyObjectRef {
    SceneObject { info }.into_ref(&vm.ctx).into()
}

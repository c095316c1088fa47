//! Lockdown: what a program cannot name, import or reach, checked before and enforced while it
//! runs.
//!
//! Two layers, because a probe of RustPython 0.5 found escapes past each one alone:
//! * [`check_code`] walks the compiled code (nested functions and classes included) and rejects
//!   `_`-prefixed names other than `_` and a short list of harmless dunders, and the attributes
//!   that lead from generators, coroutines and tracebacks to frames (`gi_frame`, `tb_frame`,
//!   `f_globals`, `mro`, ...). With `__class__`, `__globals__`, `__subclasses__`, `__import__`
//!   and `__builtins__` unnameable, the classic escapes through the type graph are closed.
//! * [`lock_builtins`] keeps an allow-list of builtins (no `open`, `exec`, `eval`, `compile`,
//!   `getattr`, `globals`, `input`, `breakpoint`, `exit`, ...), replaces `print` with a bounded
//!   capture and `__import__` with a whitelist of pre-built modules, and empties `sys.modules`.
//!
//! Input is source text or the interpreter; output is an [`Error`] naming the refused name, or a
//! locked interpreter.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::rc::Rc;

use rustpython_vm::builtins::{PyBaseExceptionRef, PyDictRef, PyStr, PyType};
use rustpython_vm::bytecode::{CodeObject, ConstantData};
use rustpython_vm::compiler::{CompileError, CompileOpts, Mode};
use rustpython_vm::function::FuncArgs;
use rustpython_vm::{AsObject, PyObjectRef, PyResult, VirtualMachine};

use super::error::Error;

/// File name the program's code reports in tracebacks.
pub(crate) const PROGRAM_FILE_NAME: &str = "<program>";

/// Dunders a program may name: methods it may define on its own classes, and the names the
/// compiler itself emits for class bodies. None of them leads to a frame, a module or a type
/// outside the program's own classes.
const ALLOWED_DUNDERS: &[&str] = &[
    // Emitted by the compiler for class bodies, annotations (Python 3.14's lazy
    // `__annotate__`), generic classes, `from __future__ import ...`, and
    // `if __name__ == "__main__":` blocks.
    "__name__",
    "__annotate__",
    "__annotate_func__",
    "__annotations__",
    "__conditional_annotations__",
    "__type_params__",
    "__future__",
    "__module__",
    "__qualname__",
    "__doc__",
    "__firstlineno__",
    "__static_attributes__",
    "__classcell__",
    "__classdictcell__",
    // Object protocol a program may implement.
    "__init__",
    "__new__",
    "__repr__",
    "__str__",
    "__format__",
    "__hash__",
    "__bool__",
    "__len__",
    "__iter__",
    "__next__",
    "__contains__",
    "__getitem__",
    "__setitem__",
    "__delitem__",
    "__call__",
    "__enter__",
    "__exit__",
    "__eq__",
    "__ne__",
    "__lt__",
    "__le__",
    "__gt__",
    "__ge__",
    "__add__",
    "__radd__",
    "__iadd__",
    "__sub__",
    "__rsub__",
    "__isub__",
    "__mul__",
    "__rmul__",
    "__imul__",
    "__truediv__",
    "__rtruediv__",
    "__floordiv__",
    "__rfloordiv__",
    "__mod__",
    "__rmod__",
    "__pow__",
    "__rpow__",
    "__neg__",
    "__pos__",
    "__abs__",
    "__int__",
    "__float__",
    "__round__",
    "__index__",
];

/// Attribute names that lead from generators, coroutines, tracebacks and functions to frames,
/// code objects, globals or the type graph. They have no leading underscore, so the prefix rule
/// alone would let them through.
const FORBIDDEN_NAMES: &[&str] = &[
    "gi_frame",
    "gi_code",
    "gi_yieldfrom",
    "gi_running",
    "gi_suspended",
    "cr_frame",
    "cr_code",
    "cr_await",
    "cr_origin",
    "cr_running",
    "cr_suspended",
    "ag_frame",
    "ag_code",
    "ag_await",
    "ag_running",
    "f_globals",
    "f_locals",
    "f_builtins",
    "f_back",
    "f_code",
    "f_trace",
    "f_lasti",
    "f_lineno",
    "tb_frame",
    "tb_next",
    "tb_lasti",
    "tb_lineno",
    "co_code",
    "co_consts",
    "co_names",
    "co_varnames",
    "cell_contents",
    "mro",
];

/// Names of cells the compiler creates for zero-argument `super()`; they hold the program's own
/// class, which `type(self)` gives anyway.
const ALLOWED_CELLS: &[&str] = &["__class__", "__classdict__"];

/// Feature names of `__future__`. The compiler has already applied them by the time the program
/// runs; the module only has to have the names for `from __future__ import annotations`.
const FUTURE_FEATURES: &[&str] = &[
    "annotations",
    "absolute_import",
    "division",
    "generator_stop",
    "generators",
    "nested_scopes",
    "print_function",
    "unicode_literals",
    "with_statement",
];

/// Builtins a program keeps (plus every exception class). Everything else (`open`, `exec`,
/// `eval`, `compile`, `getattr`, `setattr`, `delattr`, `globals`, `locals`, `vars`, `input`,
/// `breakpoint`, `help`, `exit`, `quit`, `memoryview`, `dir`, `copyright`, `credits`,
/// `license`, `__loader__`, `__spec__`, ...) is deleted.
const ALLOWED_BUILTINS: &[&str] = &[
    "abs",
    "all",
    "any",
    "ascii",
    "bin",
    "bool",
    "bytearray",
    "bytes",
    "callable",
    "chr",
    "classmethod",
    "complex",
    "dict",
    "divmod",
    "enumerate",
    "filter",
    "float",
    "format",
    "frozenset",
    "hasattr",
    "hash",
    "hex",
    "id",
    "int",
    "isinstance",
    "issubclass",
    "iter",
    "len",
    "list",
    "map",
    "max",
    "min",
    "next",
    "object",
    "oct",
    "ord",
    "pow",
    "property",
    "range",
    "repr",
    "reversed",
    "round",
    "set",
    "slice",
    "sorted",
    "staticmethod",
    "str",
    "sum",
    "super",
    "tuple",
    "type",
    "zip",
    "None",
    "Ellipsis",
    "NotImplemented",
    "False",
    "True",
    // Looked up by the VM itself for `class` statements; unnameable by programs.
    "__build_class__",
    "__name__",
    "__doc__",
    "__debug__",
];

/// Most bytes of `print` output kept per program; the rest is dropped.
const MAX_PRINTED_BYTES: usize = 64 * 1024;

/// Compiles `source` and checks every name in it (see the module docs).
pub(crate) fn compile_checked(source: &str) -> Result<CodeObject, Error> {
    let code = rustpython_vm::compiler::compile(
        source,
        Mode::Exec,
        PROGRAM_FILE_NAME,
        CompileOpts::default(),
    )
    .map_err(|error| syntax_error(&error))?;
    check_code(&code)?;
    Ok(code)
}

fn syntax_error(error: &CompileError) -> Error {
    Error::Syntax {
        message: error.to_string(),
        line: error
            .location()
            .and_then(|location| u32::try_from(location.line.get()).ok())
            .unwrap_or(0),
    }
}

/// Rejects forbidden names anywhere in `code` or the code objects nested in its constants.
pub(crate) fn check_code(code: &CodeObject) -> Result<(), Error> {
    let mut pending = vec![code];
    while let Some(code) = pending.pop() {
        // `names` holds globals, attributes and imported names: the strict rule.
        for name in &code.names {
            check_name(name, false)?;
        }
        // Locals and cells are plain variables; only the dunder list applies to them.
        for name in &code.varnames {
            check_name(name, true)?;
        }
        for name in code.cellvars.iter().chain(code.freevars.iter()) {
            if !ALLOWED_CELLS.contains(&name.as_str()) {
                check_name(name, true)?;
            }
        }
        for constant in code.constants.iter() {
            collect_nested(constant, &mut pending)?;
        }
    }
    Ok(())
}

fn collect_nested<'a>(
    constant: &'a ConstantData,
    pending: &mut Vec<&'a CodeObject>,
) -> Result<(), Error> {
    match constant {
        ConstantData::Code { code } => pending.push(code),
        ConstantData::Tuple { elements } => {
            for element in elements {
                collect_nested(element, pending)?;
            }
        }
        // Frozenset constants come only from `.pyc` files, never from this compiler; turning
        // one into an object without a VM panics inside RustPython, so refuse rather than risk it.
        ConstantData::Frozenset { .. } => {
            return Err(Error::internal(
                "the compiler produced a frozenset constant, which the sandbox cannot load",
            ));
        }
        ConstantData::Slice { .. }
        | ConstantData::Integer { .. }
        | ConstantData::Float { .. }
        | ConstantData::Complex { .. }
        | ConstantData::Boolean { .. }
        | ConstantData::Str { .. }
        | ConstantData::Bytes { .. }
        | ConstantData::None
        | ConstantData::Ellipsis => {}
    }
    Ok(())
}

/// Checks one name. `is_variable` relaxes the rule for locals: `_total` is fine as a variable,
/// never as an attribute or global.
fn check_name(name: &str, is_variable: bool) -> Result<(), Error> {
    if FORBIDDEN_NAMES.contains(&name) {
        return Err(Error::forbidden(
            name,
            format!("name `{name}` reaches interpreter internals and is not allowed"),
        ));
    }
    let is_dunder = name.starts_with("__");
    let refused = if is_dunder {
        !ALLOWED_DUNDERS.contains(&name)
    } else {
        name.starts_with('_') && name != "_" && !is_variable
    };
    if refused {
        return Err(Error::forbidden(
            name,
            format!(
                "name `{name}` is not allowed: names starting with `_` are reserved \
                 (except `_` and common dunder methods)"
            ),
        ));
    }
    Ok(())
}

/// Per-interpreter state the locked builtins share with the sandbox, reset for every program.
#[derive(Debug, Default)]
pub(crate) struct ProgramEnvironment {
    /// Modules `import` may return for the current program, by name.
    pub(crate) modules: BTreeMap<String, PyObjectRef>,
    /// The first import the whitelist refused, if any.
    pub(crate) refused_import: Option<String>,
    /// What the program printed, up to [`MAX_PRINTED_BYTES`].
    pub(crate) printed: String,
}

/// Locks the interpreter's builtins and `sys.modules` (see the module docs). `environment` is
/// read by the replacement `__import__` and written by the replacement `print`.
pub(crate) fn lock_builtins(
    vm: &VirtualMachine,
    environment: &Rc<RefCell<ProgramEnvironment>>,
) -> PyResult<()> {
    let builtins = vm.builtins.dict();
    let base_exception = vm.ctx.exceptions.base_exception_type;
    for key in builtins.keys_vec() {
        let Some(name) = key
            .downcast_ref::<PyStr>()
            .map(|name| name.to_string_lossy().into_owned())
        else {
            builtins.del_item(&*key, vm)?;
            continue;
        };
        let is_exception_class = builtins
            .get_item_opt(name.as_str(), vm)?
            .and_then(|value| value.downcast::<PyType>().ok())
            .is_some_and(|class| class.fast_issubclass(base_exception));
        if !is_exception_class && !ALLOWED_BUILTINS.contains(&name.as_str()) {
            builtins.del_item(name.as_str(), vm)?;
        }
    }

    let import_environment = Rc::clone(environment);
    let import = vm.new_function(
        "__import__",
        move |arguments: FuncArgs, vm: &VirtualMachine| {
            whitelisted_import(&import_environment, &arguments, vm)
        },
    );
    builtins.set_item("__import__", import.into(), vm)?;

    let print_environment = Rc::clone(environment);
    let print = vm.new_function("print", move |arguments: FuncArgs, vm: &VirtualMachine| {
        captured_print(&print_environment, arguments, vm)
    });
    builtins.set_item("print", print.into(), vm)?;

    // Nothing reads `sys.modules` for programs any more (imports go through the whitelist);
    // emptying it removes the importer machinery from reach should anything else leak.
    let modules = vm.sys_module.get_attr("modules", vm)?;
    if let Ok(modules) = modules.downcast::<rustpython_vm::builtins::PyDict>() {
        for key in modules.keys_vec() {
            let keep = key
                .downcast_ref::<PyStr>()
                .is_some_and(|name| matches!(name.to_string_lossy().as_ref(), "builtins" | "sys"));
            if !keep {
                modules.del_item(&*key, vm)?;
            }
        }
    }
    Ok(())
}

/// Attributes of the `__future__` module: each feature name, bound to `True`.
pub(crate) fn future_module_dict(vm: &VirtualMachine) -> PyResult<PyDictRef> {
    let dict = vm.ctx.new_dict();
    for feature in FUTURE_FEATURES {
        dict.set_item(*feature, vm.ctx.new_bool(true).into(), vm)?;
    }
    Ok(dict)
}

/// `__import__(name, globals=None, locals=None, fromlist=(), level=0)` that returns only the
/// current program's whitelisted modules.
fn whitelisted_import(
    environment: &Rc<RefCell<ProgramEnvironment>>,
    arguments: &FuncArgs,
    vm: &VirtualMachine,
) -> PyResult {
    let name: String = arguments
        .args
        .first()
        .and_then(|name| name.downcast_ref::<PyStr>())
        .map(|name| name.to_string_lossy().into_owned())
        .ok_or_else(|| vm.new_type_error("__import__() argument 1 must be str"))?;
    // Relative imports (`from . import x`, level > 0) are never whitelisted.
    let level_is_zero = arguments
        .args
        .get(4)
        .or_else(|| arguments.kwargs.get("level"))
        .is_none_or(|level| {
            level
                .clone()
                .try_into_value::<i64>(vm)
                .is_ok_and(|level| level == 0)
        });
    let mut environment = environment.borrow_mut();
    if level_is_zero && let Some(module) = environment.modules.get(&name) {
        return Ok(module.clone());
    }
    environment
        .refused_import
        .get_or_insert_with(|| name.clone());
    let allowed = environment
        .modules
        .keys()
        .map(String::as_str)
        .collect::<Vec<_>>()
        .join(", ");
    let message = format!("import of `{name}` is not allowed in the sandbox (allowed: {allowed})");
    Err(vm.new_exception_msg(
        vm.ctx.exceptions.module_not_found_error.to_owned(),
        message.into(),
    ))
}

/// Keyword arguments of `print` that are honoured; `file` and `flush` are accepted and ignored.
fn captured_print(
    environment: &Rc<RefCell<ProgramEnvironment>>,
    arguments: FuncArgs,
    vm: &VirtualMachine,
) -> PyResult {
    let FuncArgs { args, kwargs } = arguments;
    let text_of = |key: &str, default: &str| -> PyResult<String> {
        match kwargs.get(key) {
            Some(value) if !vm.is_none(value) => Ok(value.str(vm)?.to_string_lossy().into_owned()),
            _ => Ok(default.to_owned()),
        }
    };
    let separator = text_of("sep", " ")?;
    let end = text_of("end", "\n")?;
    let mut line = String::new();
    for (index, argument) in args.iter().enumerate() {
        if index > 0 {
            line.push_str(&separator);
        }
        line.push_str(&argument.str(vm)?.to_string_lossy());
    }
    line.push_str(&end);
    let mut environment = environment.borrow_mut();
    let room = MAX_PRINTED_BYTES.saturating_sub(environment.printed.len());
    if room > 0 {
        let mut cut = line.len().min(room);
        while !line.is_char_boundary(cut) {
            cut -= 1;
        }
        environment.printed.push_str(&line[..cut]);
    }
    Ok(vm.ctx.none())
}

/// Whether `exception` is an instance of the class named `class_name` or of a subclass of it.
pub(crate) fn exception_is_a(exception: &PyBaseExceptionRef, class_name: &str) -> bool {
    exception
        .class()
        .mro_collect()
        .iter()
        .any(|class| class.name().to_string() == class_name)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(source: &str) -> Result<(), Error> {
        compile_checked(source).map(|_| ())
    }

    #[test]
    fn ordinary_programs_pass() {
        let programs = [
            "x = [i * i for i in range(5)]\nanswer = sorted(x)",
            "class Vec:\n    def __init__(self, x):\n        self.x = x\n    def __repr__(self):\n        return f'Vec({self.x})'\nanswer = repr(Vec(1))",
            "class A:\n    def f(self):\n        return 1\nclass B(A):\n    def f(self):\n        return super().f() + 1\nanswer = B().f()",
            "def f():\n    total = 0\n    for _ in range(3):\n        total += 1\n    return total\nanswer = f()",
            "for _ in range(3):\n    pass\nanswer = 1",
            "def f(_hidden):\n    _local = _hidden\n    return _local\nanswer = f(1)",
            "if __name__ == '__main__':\n    answer = 1",
            "import math\nfrom math import sqrt\nanswer = math.floor(sqrt(2))",
            "try:\n    1 / 0\nexcept ZeroDivisionError as error:\n    answer = str(error)",
            "def execute_command(video):\n    return 'yes'",
            "answer = {k: v for k, v in zip('ab', (1, 2))}",
            "def gen():\n    yield 1\nanswer = list(gen())",
            "answer = 3 in {1, 2, 3}",
        ];
        for program in programs {
            check(program).unwrap_or_else(|error| panic!("{program:?} rejected: {error}"));
        }
    }

    #[test]
    fn escapes_are_rejected_by_name() {
        let cases = [
            ("().__class__.__base__.__subclasses__()", "__class__"),
            ("__import__('os')", "__import__"),
            ("__builtins__['len'] = None", "__builtins__"),
            ("def f():\n    pass\nx = f.__globals__", "__globals__"),
            ("def f():\n    pass\nx = f.__code__", "__code__"),
            ("def g():\n    yield 1\nx = g().gi_frame.f_back", "gi_frame"),
            (
                "try:\n    1/0\nexcept Exception as e:\n    t = e.__traceback__",
                "__traceback__",
            ),
            ("def f(tb):\n    return tb.tb_frame", "tb_frame"),
            ("x = object.mro()", "mro"),
            (
                "class A:\n    def m(self):\n        def inner():\n            return self.__dict__\n        return inner",
                "__dict__",
            ),
            ("_secret = 1", "_secret"),
            ("x = (1).__getattribute__('real')", "__getattribute__"),
            ("lambda: (lambda: [].__reduce_ex__(2))", "__reduce_ex__"),
        ];
        for (program, name) in cases {
            match check(program) {
                Err(Error::Forbidden { name: refused, .. }) => {
                    assert_eq!(refused, name, "{program:?}");
                }
                other => panic!("{program:?} gave {other:?}"),
            }
        }
    }

    #[test]
    fn syntax_errors_carry_the_line() {
        match check("x = 1\ny = (\n") {
            Err(Error::Syntax { line, .. }) => assert_eq!(line, 2),
            other => panic!("{other:?}"),
        }
    }
}

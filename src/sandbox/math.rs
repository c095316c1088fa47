//! A small native `math` module: the part of Python's `math` that physics-question programs use.
//!
//! RustPython keeps its real `math` in `rustpython-stdlib`, which the sandbox does not link (it
//! also carries file and process access). Input is the interpreter; output is a module object
//! built once per interpreter and copied into every program (so `math.pi = 3` in one program
//! cannot leak into the next). Errors follow CPython: a NaN from non-NaN input is
//! `ValueError("math domain error")`, an infinity from finite input is
//! `OverflowError("math range error")` where CPython raises it.
//!
//! Constants: `pi e tau inf nan`. Functions: `sqrt exp log(x[, base]) log2 log10 pow sin cos tan
//! asin acos atan atan2 hypot degrees radians fabs copysign floor ceil trunc isclose isfinite
//! isnan isinf fsum`; `floor`, `ceil` and `trunc` return `int`.

use rustpython_vm::builtins::{PyDictRef, PyInt};
use rustpython_vm::function::{ArgIntoFloat, ArgIterable, FuncArgs, OptionalArg, PosArgs};
use rustpython_vm::{AsObject, PyObjectRef, PyResult, TryFromObject, VirtualMachine};

/// Builds the dict of the `math` module (names to constants and functions).
pub(crate) fn math_module_dict(vm: &VirtualMachine) -> PyResult<PyDictRef> {
    let dict = vm.ctx.new_dict();
    let constants = [
        ("pi", std::f64::consts::PI),
        ("e", std::f64::consts::E),
        ("tau", std::f64::consts::TAU),
        ("inf", f64::INFINITY),
        ("nan", f64::NAN),
    ];
    for (name, value) in constants {
        dict.set_item(name, vm.ctx.new_float(value).into(), vm)?;
    }

    // (name, function, whether an infinite result from finite input is an overflow rather
    // than a domain error)
    let unary: [UnaryFunction; 11] = [
        ("sqrt", f64::sqrt, false),
        ("exp", f64::exp, true),
        ("log2", f64::log2, false),
        ("log10", f64::log10, false),
        ("sin", f64::sin, false),
        ("cos", f64::cos, false),
        ("tan", f64::tan, false),
        ("asin", f64::asin, false),
        ("acos", f64::acos, false),
        ("atan", f64::atan, false),
        ("fabs", f64::abs, false),
    ];
    for (name, function, can_overflow) in unary {
        let python_function = vm.new_function(name, move |x: ArgIntoFloat, vm: &VirtualMachine| {
            let x = x.into_float();
            checked(vm, x.is_finite(), x.is_nan(), function(x), can_overflow)
        });
        dict.set_item(name, python_function.into(), vm)?;
    }

    let functions: [(&'static str, PyObjectRef); 15] = [
        ("log", vm.new_function("log", log).into()),
        ("pow", vm.new_function("pow", pow).into()),
        (
            "atan2",
            vm.new_function("atan2", |y: ArgIntoFloat, x: ArgIntoFloat| {
                y.into_float().atan2(x.into_float())
            })
            .into(),
        ),
        ("hypot", vm.new_function("hypot", hypot).into()),
        (
            "degrees",
            vm.new_function("degrees", |x: ArgIntoFloat| x.into_float().to_degrees())
                .into(),
        ),
        (
            "radians",
            vm.new_function("radians", |x: ArgIntoFloat| x.into_float().to_radians())
                .into(),
        ),
        (
            "copysign",
            vm.new_function("copysign", |x: ArgIntoFloat, y: ArgIntoFloat| {
                x.into_float().copysign(y.into_float())
            })
            .into(),
        ),
        (
            "floor",
            vm.new_function("floor", |x: PyObjectRef, vm: &VirtualMachine| {
                to_integral(vm, x, f64::floor)
            })
            .into(),
        ),
        (
            "ceil",
            vm.new_function("ceil", |x: PyObjectRef, vm: &VirtualMachine| {
                to_integral(vm, x, f64::ceil)
            })
            .into(),
        ),
        (
            "trunc",
            vm.new_function("trunc", |x: PyObjectRef, vm: &VirtualMachine| {
                to_integral(vm, x, f64::trunc)
            })
            .into(),
        ),
        ("isclose", vm.new_function("isclose", isclose).into()),
        (
            "isfinite",
            vm.new_function("isfinite", |x: ArgIntoFloat| x.into_float().is_finite())
                .into(),
        ),
        (
            "isnan",
            vm.new_function("isnan", |x: ArgIntoFloat| x.into_float().is_nan())
                .into(),
        ),
        (
            "isinf",
            vm.new_function("isinf", |x: ArgIntoFloat| x.into_float().is_infinite())
                .into(),
        ),
        (
            "fsum",
            vm.new_function(
                "fsum",
                |values: ArgIterable<ArgIntoFloat>, vm: &VirtualMachine| fsum(&values, vm),
            )
            .into(),
        ),
    ];
    for (name, object) in functions {
        dict.set_item(name, object, vm)?;
    }
    Ok(dict)
}

/// A one-argument float function: its name, the function, and whether an infinite result from
/// finite input is an overflow (`exp`) rather than a domain error (`log(0)`).
type UnaryFunction = (&'static str, fn(f64) -> f64, bool);

/// CPython's `math_1` error rule: NaN out of non-NaN in is a domain error; an infinity out of
/// finite input is an overflow (`can_overflow`) or a domain error (poles such as `log(0)`).
fn checked(
    vm: &VirtualMachine,
    input_finite: bool,
    input_nan: bool,
    output: f64,
    can_overflow: bool,
) -> PyResult<f64> {
    if output.is_nan() && !input_nan {
        return Err(vm.new_value_error("math domain error"));
    }
    if output.is_infinite() && input_finite {
        return Err(if can_overflow {
            vm.new_overflow_error("math range error")
        } else {
            vm.new_value_error("math domain error")
        });
    }
    Ok(output)
}

fn log(x: ArgIntoFloat, base: OptionalArg<ArgIntoFloat>, vm: &VirtualMachine) -> PyResult<f64> {
    let x = x.into_float();
    let natural = checked(vm, x.is_finite(), x.is_nan(), x.ln(), false)?;
    match base {
        OptionalArg::Missing => Ok(natural),
        OptionalArg::Present(base) => {
            let base = base.into_float();
            let base_log = checked(vm, base.is_finite(), base.is_nan(), base.ln(), false)?;
            if base_log == 0.0 {
                return Err(vm.new_zero_division_error("float division by zero"));
            }
            Ok(natural / base_log)
        }
    }
}

fn pow(x: ArgIntoFloat, y: ArgIntoFloat, vm: &VirtualMachine) -> PyResult<f64> {
    let (x, y) = (x.into_float(), y.into_float());
    let result = x.powf(y);
    let inputs_finite = x.is_finite() && y.is_finite();
    if result.is_nan() && !x.is_nan() && !y.is_nan() {
        return Err(vm.new_value_error("math domain error"));
    }
    if result.is_infinite() && inputs_finite {
        // 0 ** negative is a pole (domain error); anything else finite is an overflow.
        return Err(if x == 0.0 {
            vm.new_value_error("math domain error")
        } else {
            vm.new_overflow_error("math range error")
        });
    }
    Ok(result)
}

fn hypot(coordinates: PosArgs<ArgIntoFloat>) -> f64 {
    coordinates
        .into_vec()
        .into_iter()
        .map(ArgIntoFloat::into_float)
        .fold(0.0, f64::hypot)
}

/// `floor`/`ceil`/`trunc`: an `int` stays itself; anything else goes through float, and the
/// integral float becomes an `int` through Python's own `int()` (which raises on NaN and
/// infinities exactly as CPython's `math.floor` does).
fn to_integral(vm: &VirtualMachine, x: PyObjectRef, round: fn(f64) -> f64) -> PyResult {
    if x.downcast_ref::<PyInt>().is_some() {
        return Ok(x);
    }
    let value = ArgIntoFloat::try_from_object(vm, x)?.into_float();
    vm.ctx
        .types
        .int_type
        .as_object()
        .call((vm.ctx.new_float(round(value)),), vm)
}

/// `math.isclose(a, b, *, rel_tol=1e-09, abs_tol=0.0)`.
fn isclose(mut arguments: FuncArgs, vm: &VirtualMachine) -> PyResult<bool> {
    let mut tolerance = |name: &str, default: f64| -> PyResult<f64> {
        arguments.take_keyword(name).map_or(Ok(default), |value| {
            ArgIntoFloat::try_from_object(vm, value).map(ArgIntoFloat::into_float)
        })
    };
    let relative = tolerance("rel_tol", 1e-9)?;
    let absolute = tolerance("abs_tol", 0.0)?;
    let (a, b): (ArgIntoFloat, ArgIntoFloat) = arguments.bind(vm)?;
    let (a, b) = (a.into_float(), b.into_float());
    if relative < 0.0 || absolute < 0.0 {
        return Err(vm.new_value_error("tolerances must be non-negative"));
    }
    #[expect(
        clippy::float_cmp,
        reason = "exact equality is CPython's first isclose case"
    )]
    if a == b {
        return Ok(true);
    }
    if a.is_infinite() || b.is_infinite() {
        return Ok(false);
    }
    let difference = (b - a).abs();
    Ok(difference <= (relative * b).abs()
        || difference <= (relative * a).abs()
        || difference <= absolute)
}

/// `math.fsum`: Shewchuk's exact summation with partials, as CPython's `msum`.
fn fsum(values: &ArgIterable<ArgIntoFloat>, vm: &VirtualMachine) -> PyResult<f64> {
    let mut partials: Vec<f64> = Vec::new();
    let mut special_sum = 0.0;
    let mut all_finite = true;
    for value in values.iter(vm)? {
        let mut x = value?.into_float();
        if !x.is_finite() {
            // Infinities and NaNs cannot be added exactly; track them apart as CPython does.
            all_finite = false;
            special_sum += x;
            continue;
        }
        let mut kept = 0;
        for index in 0..partials.len() {
            let mut y = partials[index];
            if x.abs() < y.abs() {
                std::mem::swap(&mut x, &mut y);
            }
            let high = x + y;
            let low = y - (high - x);
            if low != 0.0 {
                partials[kept] = low;
                kept += 1;
            }
            x = high;
        }
        partials.truncate(kept);
        partials.push(x);
    }
    if !all_finite {
        if special_sum.is_nan() {
            return Err(vm.new_value_error("-inf + inf in fsum"));
        }
        return Ok(special_sum);
    }
    Ok(round_partials(&partials))
}

/// Adds the non-overlapping partials from the largest down, with CPython's correction for a
/// sum that lands exactly halfway between two floats.
fn round_partials(partials: &[f64]) -> f64 {
    let Some((&last, rest)) = partials.split_last() else {
        return 0.0;
    };
    let mut high = last;
    let mut low = 0.0;
    let mut remaining = rest;
    while let Some((&y, smaller)) = remaining.split_last() {
        remaining = smaller;
        let x = high;
        high = x + y;
        low = y - (high - x);
        if low != 0.0 {
            break;
        }
    }
    if let Some(&next) = remaining.last()
        && ((low < 0.0 && next < 0.0) || (low > 0.0 && next > 0.0))
    {
        let doubled = low * 2.0;
        let candidate = high + doubled;
        #[expect(
            clippy::float_cmp,
            reason = "CPython's exactness test for the half-way case"
        )]
        if doubled == candidate - high {
            high = candidate;
        }
    }
    high
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_partials_is_exact_where_naive_summation_is_not() {
        // Partials as fsum([1e16, 1.0, 1e-16]) leaves them, smallest first.
        let exact = |partials: &[f64], expected: f64| {
            assert_eq!(
                round_partials(partials).to_bits(),
                expected.to_bits(),
                "{partials:?}"
            );
        };
        exact(&[], 0.0);
        exact(&[1e-16, 1.0, 1e16], 1e16 + 2.0);
        exact(&[0.1], 0.1);
    }
}

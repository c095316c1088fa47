//! Process resource limits of a worker: `RLIMIT_AS`, `RLIMIT_CPU`, `RLIMIT_CORE`, and the
//! process's CPU time so far.
//!
//! Input is a budget; output is the limit set on the calling process (or the OS error). This is
//! the only place in the sandbox with `unsafe`: each block is one libc call on a stack value.
//! Only soft limits are set, and never above the hard limit: an unprivileged process cannot raise
//! a hard limit again once lowered, and the worker needs a fresh CPU limit per request.

use std::io;
use std::time::Duration;

/// Current (soft, hard) values of `resource`.
fn get_limit(resource: libc::__rlimit_resource_t) -> io::Result<libc::rlimit> {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: `limit` is a valid, writable `rlimit`; getrlimit only writes into it.
    #[expect(unsafe_code, reason = "getrlimit has no safe wrapper in std")]
    let status = unsafe { libc::getrlimit(resource, &raw mut limit) };
    if status == 0 {
        Ok(limit)
    } else {
        Err(io::Error::last_os_error())
    }
}

/// Sets the soft limit of `resource` to `soft`, capped at the hard limit.
fn set_soft_limit(resource: libc::__rlimit_resource_t, soft: u64) -> io::Result<()> {
    let current = get_limit(resource)?;
    let limit = libc::rlimit {
        rlim_cur: soft.min(current.rlim_max),
        rlim_max: current.rlim_max,
    };
    // SAFETY: `limit` is a valid `rlimit` that setrlimit only reads.
    #[expect(unsafe_code, reason = "setrlimit has no safe wrapper in std")]
    let status = unsafe { libc::setrlimit(resource, &raw const limit) };
    if status == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

/// Caps the worker's address space: allocations beyond it fail, which RustPython mostly turns
/// into `MemoryError` (measured on RustPython 0.5) instead of growing until the machine's OOM
/// killer steps in.
pub(crate) fn limit_address_space(bytes: u64) -> io::Result<()> {
    set_soft_limit(libc::RLIMIT_AS, bytes)
}

/// Turns off core dumps: a worker killed by `SIGXCPU` or an abort must not leave a core file.
pub(crate) fn disable_core_dumps() -> io::Result<()> {
    set_soft_limit(libc::RLIMIT_CORE, 0)
}

/// Lets the process use `budget` more CPU time (whole seconds, rounded up) before `SIGXCPU`.
pub(crate) fn limit_cpu_time_from_now(budget: Duration) -> io::Result<()> {
    let used = process_cpu_time()?;
    let limit_seconds = (used + budget).as_secs_f64().ceil();
    // Float to integer seconds: the value is a small positive number of seconds.
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a positive, rounded-up count of seconds far below u64::MAX"
    )]
    let limit_seconds = limit_seconds as u64;
    set_soft_limit(libc::RLIMIT_CPU, limit_seconds.max(1))
}

/// User plus system CPU time of the whole process so far.
pub(crate) fn process_cpu_time() -> io::Result<Duration> {
    // SAFETY: an all-zero `rusage` is a valid value of this plain C struct.
    #[expect(
        unsafe_code,
        reason = "zero-initialising a plain C struct for getrusage"
    )]
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `usage` is a valid, writable `rusage`; getrusage only writes into it.
    #[expect(unsafe_code, reason = "getrusage has no safe wrapper in std")]
    let status = unsafe { libc::getrusage(libc::RUSAGE_SELF, &raw mut usage) };
    if status != 0 {
        return Err(io::Error::last_os_error());
    }
    let to_duration = |time: libc::timeval| {
        let seconds = u64::try_from(time.tv_sec).unwrap_or(0);
        let micros = u32::try_from(time.tv_usec).unwrap_or(0);
        Duration::from_secs(seconds) + Duration::from_micros(u64::from(micros))
    };
    Ok(to_duration(usage.ru_utime) + to_duration(usage.ru_stime))
}

/// The conventional name of signal `signal`, e.g. `SIGABRT`.
pub(crate) fn signal_name(signal: i32) -> String {
    let name = match signal {
        libc::SIGABRT => "SIGABRT",
        libc::SIGBUS => "SIGBUS",
        libc::SIGFPE => "SIGFPE",
        libc::SIGILL => "SIGILL",
        libc::SIGKILL => "SIGKILL",
        libc::SIGSEGV => "SIGSEGV",
        libc::SIGTERM => "SIGTERM",
        libc::SIGXCPU => "SIGXCPU",
        libc::SIGXFSZ => "SIGXFSZ",
        libc::SIGPIPE => "SIGPIPE",
        libc::SIGINT => "SIGINT",
        _ => return format!("signal {signal}"),
    };
    name.to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cpu_time_is_measured_and_grows() {
        let before = process_cpu_time().unwrap();
        let mut spin = 0_u64;
        for index in 0..20_000_000_u64 {
            spin = spin.wrapping_add(index ^ (spin >> 3));
        }
        std::hint::black_box(spin);
        let after = process_cpu_time().unwrap();
        assert!(after > before, "{before:?} -> {after:?}");
    }

    #[test]
    fn signal_names() {
        assert_eq!(signal_name(libc::SIGXCPU), "SIGXCPU");
        assert_eq!(signal_name(1000), "signal 1000");
    }
}

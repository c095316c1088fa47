//! Command errors, classed as the user's (exit 1: bad path, bad data, bad flags) or ours
//! (exit 2: a worker that cannot start, an I/O failure writing our own files).

/// Whose problem an error is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorClass {
    /// Bad input: paths, data files, settings. Exit 1.
    User,
    /// A failure of the tool itself. Exit 2.
    Internal,
}

/// An error that ends a command.
#[derive(Debug)]
pub struct AppError {
    /// Whose problem it is.
    pub class: ErrorClass,
    /// The error with its context chain.
    pub error: anyhow::Error,
}

/// Classifies errors at the point where the class is known.
pub(crate) trait Classify<T> {
    /// A user or data error.
    fn user(self) -> Result<T, AppError>;
    /// An internal error.
    fn internal(self) -> Result<T, AppError>;
}

impl<T, E: Into<anyhow::Error>> Classify<T> for Result<T, E> {
    fn user(self) -> Result<T, AppError> {
        self.map_err(|e| AppError {
            class: ErrorClass::User,
            error: e.into(),
        })
    }

    fn internal(self) -> Result<T, AppError> {
        self.map_err(|e| AppError {
            class: ErrorClass::Internal,
            error: e.into(),
        })
    }
}

/// A user error from a message.
pub(crate) fn user_error(message: impl std::fmt::Display) -> AppError {
    AppError {
        class: ErrorClass::User,
        error: anyhow::anyhow!("{message}"),
    }
}

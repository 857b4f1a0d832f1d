//! The one error type of the command, and its exit codes.
//!
//! | exit code | meaning |
//! |---|---|
//! | 0 | success |
//! | 1 | the work failed while running (disk full, write error) |
//! | 2 | bad input: arguments, parameter values, presets, destinations — nothing was written |
//!
//! Every error prints as a single `error: …` line on stderr that names the offending
//! argument, parameter or file and, where one exists, the allowed range.

use std::fmt;

/// Exit code for bad input (the same code clap uses for usage errors).
pub const EXIT_INPUT: u8 = 2;
/// Exit code for a failure while working.
pub const EXIT_FAILURE: u8 = 1;

/// Why a command failed.
#[derive(Debug)]
pub enum CliError {
    /// The invocation or one of its inputs is wrong; the user can fix it. Exit code 2.
    Input(String),
    /// Something failed while working (I/O). Exit code 1.
    Failure(String),
}

impl CliError {
    /// The process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => EXIT_INPUT,
            CliError::Failure(_) => EXIT_FAILURE,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let msg = match self {
            CliError::Input(m) | CliError::Failure(m) => m,
        };
        // One line, whatever the message embeds (file contents, OS messages).
        for c in msg.chars() {
            if c == '\n' || c == '\r' {
                f.write_str(" ")?;
            } else {
                write!(f, "{c}")?;
            }
        }
        Ok(())
    }
}

/// Shorthand for a bad-input error.
pub fn input(msg: impl Into<String>) -> CliError {
    CliError::Input(msg.into())
}

/// Shorthand for a failure while working.
pub fn failure(msg: impl Into<String>) -> CliError {
    CliError::Failure(msg.into())
}

/// Quote user-supplied text for an error message (control characters escaped): the file
/// layer's rule, so the command and the readers quote alike.
pub use trundle_io::quote;

/// A recording that cannot be decoded is bad input; the decoder's message names the file.
impl From<trundle_io::recording::RecordingError> for CliError {
    fn from(e: trundle_io::recording::RecordingError) -> Self {
        input(e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_are_one_line_and_codes_are_right() {
        let e = input("a\nb");
        assert_eq!(e.to_string(), "a b");
        assert_eq!(e.exit_code(), 2);
        assert_eq!(failure("x").exit_code(), 1);
        assert_eq!(quote("a\nb"), "'a\\nb'");
    }
}

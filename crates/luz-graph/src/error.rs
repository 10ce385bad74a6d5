//! Errors of declaring, compiling and executing a graph.

use std::fmt;

/// The error a record closure returns: any error, boxed (luz's own errors convert with `?`).
pub type PassError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// Why a graph could not be compiled or executed.
#[derive(Debug)]
pub enum GraphError {
    /// A pass used a resource it did not declare.
    Undeclared {
        /// The pass.
        pass: &'static str,
        /// The resource's name.
        resource: String,
    },
    /// A pass reads (part of) a resource whose contents nothing defined before it: a transient
    /// no earlier pass wrote, or an imported image whose contents are not kept.
    ReadBeforeWrite {
        /// The pass.
        pass: &'static str,
        /// The resource's name.
        resource: String,
    },
    /// A declaration does not fit its access kind or resource.
    InvalidUse {
        /// The pass.
        pass: &'static str,
        /// The resource's name (or handle).
        resource: String,
        /// What is wrong.
        reason: String,
    },
    /// A pass declared the same subresource with two accesses needing different layouts.
    ConflictingAccess {
        /// The pass.
        pass: &'static str,
        /// The resource's name.
        resource: String,
        /// The first access's name.
        first: &'static str,
        /// The second access's name.
        second: &'static str,
    },
    /// A handle that does not belong to this graph.
    InvalidHandle {
        /// Where it was used.
        pass: &'static str,
        /// The handle, printed.
        handle: String,
    },
    /// A record closure failed.
    Pass {
        /// The pass.
        pass: &'static str,
        /// Its error.
        source: PassError,
    },
    /// The image factory could not create a transient.
    Allocation {
        /// The transient's name.
        resource: String,
        /// The factory's error.
        source: PassError,
    },
}

impl fmt::Display for GraphError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GraphError::Undeclared { pass, resource } => write!(
                f,
                "pass \"{pass}\" uses \"{resource}\" without declaring it"
            ),
            GraphError::ReadBeforeWrite { pass, resource } => write!(
                f,
                "pass \"{pass}\" reads \"{resource}\" but no earlier pass writes it (and its \
                 contents are not imported)"
            ),
            GraphError::InvalidUse {
                pass,
                resource,
                reason,
            } => write!(f, "pass \"{pass}\", resource \"{resource}\": {reason}"),
            GraphError::ConflictingAccess {
                pass,
                resource,
                first,
                second,
            } => write!(
                f,
                "pass \"{pass}\" declares \"{resource}\" as {first} and as {second}, which need \
                 different layouts"
            ),
            GraphError::InvalidHandle { pass, handle } => {
                write!(
                    f,
                    "pass \"{pass}\" uses {handle}, not a handle of this graph"
                )
            }
            GraphError::Pass { pass, source } => write!(f, "pass \"{pass}\" failed: {source}"),
            GraphError::Allocation { resource, source } => {
                write!(f, "could not create transient \"{resource}\": {source}")
            }
        }
    }
}

impl std::error::Error for GraphError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            GraphError::Pass { source, .. } | GraphError::Allocation { source, .. } => {
                Some(source.as_ref())
            }
            _ => None,
        }
    }
}

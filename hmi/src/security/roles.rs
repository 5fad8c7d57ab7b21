//! Roles: what a token may do, and the role each route needs.
//!
//! Invariant: every method other than GET and HEAD needs at least `operator`, and every
//! state-changing route not listed here needs `integrator`, so a route added later is closed
//! until someone opens it on purpose.

use axum::http::Method;

/// What a session may do; each role includes the ones before it.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// Reads the API and the WebSocket.
    Viewer,
    /// A viewer who also gives commands: START, HOLD, RESET, mode, MDI, acknowledge.
    Operator,
    /// An operator who also writes, forces, unforces and switches the power flow.
    Integrator,
}

impl Role {
    /// The role's name as the token file and the errors spell it.
    pub fn name(self) -> &'static str {
        match self {
            Role::Viewer => "viewer",
            Role::Operator => "operator",
            Role::Integrator => "integrator",
        }
    }

    /// The role named `text`, if any.
    pub fn parse(text: &str) -> Option<Role> {
        match text {
            "viewer" => Some(Role::Viewer),
            "operator" => Some(Role::Operator),
            "integrator" => Some(Role::Integrator),
            _ => None,
        }
    }
}

impl std::fmt::Display for Role {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The role a request needs: reads need `viewer`, `POST /api/command` needs `operator`, every
/// other state-changing request (write, force, unforce, flow, anything unknown) `integrator`.
pub fn required(method: &Method, path: &str) -> Role {
    if method == Method::GET || method == Method::HEAD {
        return Role::Viewer;
    }
    if method == Method::POST && path == "/api/command" {
        return Role::Operator;
    }
    Role::Integrator
}

/// What a request is, for the error naming the role it needs.
pub fn what(method: &Method, path: &str) -> &'static str {
    match (method.as_str(), path) {
        ("POST", "/api/command") => {
            "operator commands (START, HOLD, RESET, mode, MDI, acknowledge)"
        }
        ("POST", "/api/write") => "writes",
        ("POST", "/api/force") => "forces",
        ("DELETE", _) => "unforcing",
        ("POST", "/api/flow") => "switching the power flow",
        _ => "this request",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_route_needs_the_role_of_the_issue() {
        let cases = [
            (Method::GET, "/api/status", Role::Viewer),
            (Method::GET, "/ws", Role::Viewer),
            (Method::HEAD, "/", Role::Viewer),
            (Method::POST, "/api/command", Role::Operator),
            (Method::POST, "/api/write", Role::Integrator),
            (Method::POST, "/api/force", Role::Integrator),
            (Method::DELETE, "/api/force", Role::Integrator),
            (Method::DELETE, "/api/force/I0A3", Role::Integrator),
            (Method::POST, "/api/flow", Role::Integrator),
            // Unknown or odd spellings stay closed.
            (Method::POST, "/api/command/", Role::Integrator),
            (Method::PUT, "/api/command", Role::Integrator),
            (Method::PATCH, "/api/status", Role::Integrator),
        ];
        for (m, p, want) in cases {
            assert_eq!(required(&m, p), want, "{m} {p}");
        }
        assert!(Role::Viewer < Role::Operator && Role::Operator < Role::Integrator);
        for r in [Role::Viewer, Role::Operator, Role::Integrator] {
            assert_eq!(Role::parse(r.name()), Some(r));
        }
        assert_eq!(Role::parse("admin"), None);
    }
}

//! Who may do what: the endpoints the server offers and its [`AuthManager`]. On a loopback
//! address the one endpoint is SecurityPolicy None with anonymous sessions (and the users of the
//! users file, if any); anywhere else the endpoints are Basic256Sha256 Sign and SignAndEncrypt
//! with the server certificate the stack creates on first start in `<machine>/opcua-pki/`, user
//! name and password only (anonymous refused). Roles are the web HMI's: a viewer browses, reads
//! and subscribes; an operator also calls methods (a channel's START, HOLD, RESET); an integrator also
//! writes inside the io.toml window.
//!
//! **Invariants:** anonymous sessions exist only on loopback, where they are integrators without a
//! users file and viewers with one; a role lacking the right sees `CurrentWrite` removed from the
//! user access level (writes answer `BadUserAccessDenied`) and methods not user-executable.

use std::collections::BTreeSet;

use async_trait::async_trait;
use hmi::security::Role;
use opcua::crypto::SecurityPolicy;
use opcua::nodes::AccessLevel;
use opcua::server::authenticator::{
    AuthManager, Password, UserToken, user_pass_security_policy_id, user_pass_security_policy_uri,
};
use opcua::server::{ANONYMOUS_USER_TOKEN_ID, ServerBuilder, ServerEndpoint, ServerUserToken};
use opcua::types::{
    Error, MessageSecurityMode, NodeId, StatusCode, UAString, UserTokenPolicy, UserTokenType,
};

use crate::users::Users;

/// The authenticator.
pub struct Auth {
    users: Users,
    anonymous: Option<Role>,
}

impl Auth {
    /// The rights of `users` (and of anonymous sessions on loopback).
    pub fn new(users: Users, loopback: bool) -> Auth {
        let anonymous = loopback.then(|| {
            if users.is_empty() {
                Role::Integrator
            } else {
                Role::Viewer
            }
        });
        Auth { users, anonymous }
    }

    /// The role of a session's token (None: anonymous off loopback, or an unknown user).
    pub fn role(&self, token: &UserToken) -> Option<Role> {
        if token.is_anonymous() {
            self.anonymous
        } else {
            self.users.role(&token.0)
        }
    }
}

/// Adds the endpoints (and the users' token ids) for `loopback` to `builder`.
pub fn endpoints(
    mut builder: ServerBuilder,
    users: &[(String, String)],
    loopback: bool,
) -> ServerBuilder {
    let mut ids: Vec<String> = Vec::new();
    for (user, pass) in users {
        builder = builder.add_user_token(
            user.clone(),
            ServerUserToken {
                user: user.clone(),
                pass: Some(pass.clone()),
                ..Default::default()
            },
        );
        ids.push(user.clone());
    }
    if loopback {
        ids.push(ANONYMOUS_USER_TOKEN_ID.to_string());
        builder
            .add_endpoint("none", ServerEndpoint::new_none("/", &ids))
            .discovery_urls(vec!["/".to_owned()])
    } else {
        builder
            .add_endpoint(
                "basic256sha256_sign",
                // The brief's policy; async-opcua marks the Sign-only constructor deprecated.
                ServerEndpoint::new(
                    "/",
                    SecurityPolicy::Basic256Sha256,
                    MessageSecurityMode::Sign,
                    &ids,
                ),
            )
            .add_endpoint(
                "basic256sha256_sign_encrypt",
                ServerEndpoint::new_basic256sha256_sign_encrypt("/", &ids),
            )
            .discovery_urls(vec!["/".to_owned()])
            .create_sample_keypair(true)
            .certificate_path("own/cert.der")
            .private_key_path("private/private.pem")
    }
}

fn rejected(what: &str) -> Error {
    Error::new(StatusCode::BadIdentityTokenRejected, what.to_string())
}

#[async_trait]
impl AuthManager for Auth {
    async fn authenticate_anonymous_token(&self, endpoint: &ServerEndpoint) -> Result<(), Error> {
        if self.anonymous.is_some() && endpoint.user_token_ids.contains(ANONYMOUS_USER_TOKEN_ID) {
            Ok(())
        } else {
            Err(rejected("anonymous sessions are refused off loopback"))
        }
    }

    async fn authenticate_username_identity_token(
        &self,
        _endpoint: &ServerEndpoint,
        username: &str,
        password: &Password,
    ) -> Result<UserToken, Error> {
        match self.users.check(username, password.get()) {
            Some(_) => Ok(UserToken(username.to_string())),
            None => Err(rejected("wrong user name or password")),
        }
    }

    fn effective_user_access_level(
        &self,
        token: &UserToken,
        user_access_level: AccessLevel,
        _node_id: &NodeId,
    ) -> AccessLevel {
        if self.role(token) == Some(Role::Integrator) {
            user_access_level
        } else {
            user_access_level - AccessLevel::CURRENT_WRITE
        }
    }

    fn is_user_executable(&self, token: &UserToken, _method_id: &NodeId) -> bool {
        self.role(token) >= Some(Role::Operator)
    }

    fn user_token_policies(&self, endpoint: &ServerEndpoint) -> Vec<UserTokenPolicy> {
        let ids: &BTreeSet<String> = &endpoint.user_token_ids;
        let mut out = Vec::new();
        if self.anonymous.is_some() && ids.contains(ANONYMOUS_USER_TOKEN_ID) {
            out.push(UserTokenPolicy {
                policy_id: UAString::from("anonymous"),
                token_type: UserTokenType::Anonymous,
                issued_token_type: UAString::null(),
                issuer_endpoint_url: UAString::null(),
                security_policy_uri: UAString::null(),
            });
        }
        if !self.users.is_empty() {
            out.push(UserTokenPolicy {
                policy_id: user_pass_security_policy_id(endpoint),
                token_type: UserTokenType::UserName,
                issued_token_type: UAString::null(),
                issuer_endpoint_url: UAString::null(),
                security_policy_uri: user_pass_security_policy_uri(endpoint),
            });
        }
        out
    }
}

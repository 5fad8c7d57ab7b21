//! Sessions: a request presents its token as a cookie (what the page uses), an
//! `Authorization: Bearer` header (programs) or a `token=` query parameter (the start URL).
//!
//! Opening the start URL (`GET /?token=…`) answers `303 See Other` to `/` with the token in a
//! cookie (`HttpOnly`: no script reads it; `SameSite=Strict`: no other site's page sends it;
//! `Secure` under TLS), so the address bar and the history no longer show it and the page works
//! without the query. The cookie is named after the port (`ncplc_hmi_8080`), since browsers
//! share cookies between the ports of one host.

use axum::http::{HeaderMap, HeaderValue, Uri, header};
use axum::response::{IntoResponse, Response};

/// The cookie that carries the token for the server on `port`.
pub fn cookie_name(port: u16) -> String {
    format!("ncplc_hmi_{port}")
}

/// Where a request's token came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Presented {
    /// The session cookie.
    Cookie(String),
    /// `Authorization: Bearer`.
    Bearer(String),
    /// The `token=` query parameter.
    Query(String),
}

impl Presented {
    /// The token itself.
    pub fn token(&self) -> &str {
        match self {
            Presented::Cookie(t) | Presented::Bearer(t) | Presented::Query(t) => t,
        }
    }
}

/// Every token a request presents, in the order header, query, cookie.
pub fn presented(headers: &HeaderMap, uri: &Uri, port: u16) -> Vec<Presented> {
    let mut out = Vec::new();
    for v in headers.get_all(header::AUTHORIZATION) {
        if let Ok(s) = v.to_str()
            && let Some(t) = s.strip_prefix("Bearer ")
        {
            out.push(Presented::Bearer(t.trim().to_string()));
        }
    }
    if let Some(q) = uri.query() {
        out.extend(
            q.split('&')
                .filter_map(|kv| kv.strip_prefix("token="))
                .map(|t| Presented::Query(t.to_string())),
        );
    }
    let name = cookie_name(port);
    for v in headers.get_all(header::COOKIE) {
        let Ok(s) = v.to_str() else { continue };
        out.extend(s.split(';').filter_map(|c| {
            let (k, v) = c.trim().split_once('=')?;
            (k == name).then(|| Presented::Cookie(v.to_string()))
        }));
    }
    out
}

/// The answer to the start URL: to `/` (the query dropped), with the session cookie.
pub fn start_redirect(token: &str, port: u16, tls: bool) -> Response {
    let secure = if tls { "; Secure" } else { "" };
    let cookie = format!(
        "{}={token}; Path=/; HttpOnly; SameSite=Strict{secure}",
        cookie_name(port)
    );
    let mut r = (
        axum::http::StatusCode::SEE_OTHER,
        [(header::LOCATION, HeaderValue::from_static("/"))],
    )
        .into_response();
    // Tokens are checked to be URL- and cookie-safe ASCII, so this does not fail for a known token.
    if let Ok(v) = HeaderValue::from_str(&cookie) {
        r.headers_mut().insert(header::SET_COOKIE, v);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_come_from_header_query_and_cookie() {
        let mut h = HeaderMap::new();
        h.insert(
            header::AUTHORIZATION,
            HeaderValue::from_static("Bearer abc "),
        );
        h.insert(
            header::COOKIE,
            HeaderValue::from_static("other=1; ncplc_hmi_8080=ck; ncplc_hmi_8081=no"),
        );
        let uri: Uri = "/ws?ack=1&token=q".parse().expect("uri");
        assert_eq!(
            presented(&h, &uri, 8080),
            [
                Presented::Bearer("abc".into()),
                Presented::Query("q".into()),
                Presented::Cookie("ck".into())
            ]
        );
        assert!(presented(&HeaderMap::new(), &"/".parse().expect("uri"), 8080).is_empty());
    }

    #[test]
    fn the_start_redirect_sets_a_strict_http_only_cookie() {
        let r = start_redirect("t0123456789abcdef", 8080, false);
        assert_eq!(r.status(), 303);
        assert_eq!(r.headers()[header::LOCATION], "/");
        assert_eq!(
            r.headers()[header::SET_COOKIE],
            "ncplc_hmi_8080=t0123456789abcdef; Path=/; HttpOnly; SameSite=Strict"
        );
        let r = start_redirect("t0123456789abcdef", 443, true);
        assert!(
            r.headers()[header::SET_COOKIE]
                .to_str()
                .expect("ascii")
                .ends_with("; Secure")
        );
    }
}

//! Who may use the page's server (issue 45): every request's `Host`, every `Origin`, and the
//! session's token for driving.
//!
//! - **Host**: a request is answered only when its `Host` names the server itself: a loopback
//!   name (`127.0.0.1`, `localhost`, `[::1]`) or a name given with `--allow-host`, with the
//!   server's port; the address of a non-loopback `--bind` is allowed too, and with an
//!   unspecified one (`0.0.0.0`, `::`) any IP literal (a browser that sends an IP literal
//!   opened that address itself). A web page of another site that rebinds its DNS name to this
//!   machine (DNS rebinding) sends its own name: refused.
//! - **Origin**: a request that carries an `Origin` (browsers send one on every WebSocket
//!   upgrade and every cross-site fetch) is answered only when it is the server's own
//!   (`http://` + an allowed host) or one given with `--allow-origin`: a page of another site
//!   can neither open the WebSocket nor read the server's data. A request without one comes
//!   from a program, not from a web page (Python, the tests, curl): it may watch.
//! - **Token**: driving (a seat, and with it reset and stop) needs the session's token
//!   ([`SessionToken`], 128 random bits), presented as `/ws?session=TOKEN`. The page the server
//!   serves reads it from `/session.json` (same origin: the checks above keep other sites from
//!   reading it); the terminal prints it for other clients.
//!
//! Refused requests are answered `403 Forbidden` with a one-line reason.

use std::net::IpAddr;

/// The loopback names every server answers to.
const LOOPBACK_NAMES: [&str; 3] = ["127.0.0.1", "localhost", "[::1]"];

/// Longest name `--allow-host` or `--allow-origin` takes, characters.
pub const MAX_ALLOWED_NAME: usize = 253;

/// Who may use a server: the hosts and origins allowed besides the server's own.
#[derive(Clone, Debug, Default)]
pub struct Access {
    /// Extra host names or IP literals (lower case, without a port; IPv6 in brackets).
    hosts: Vec<String>,
    /// Extra origins (`scheme://host[:port]`, lower case, no trailing `/`).
    origins: Vec<String>,
    /// The server's port (set when it binds).
    port: u16,
    /// The bind address when it is not loopback.
    bind: Option<IpAddr>,
}

/// Why a request was refused: the 403 body.
pub type Refusal = &'static str;

impl Access {
    /// Only the loopback names (the default).
    pub fn loopback() -> Access {
        Access::default()
    }

    /// Also answers requests whose `Host` is `name` (a host name or IP literal, an IPv6 one in
    /// brackets, without a port: the server's port is required).
    pub fn allow_host(mut self, name: &str) -> Result<Access, String> {
        let n = name.trim().to_ascii_lowercase();
        let plain = |c: char| c.is_ascii_alphanumeric() || matches!(c, '-' | '.' | '_');
        let v6 = n
            .strip_prefix('[')
            .and_then(|r| r.strip_suffix(']'))
            .is_some_and(|a| a.parse::<std::net::Ipv6Addr>().is_ok());
        if n.is_empty() || n.len() > MAX_ALLOWED_NAME || !(v6 || n.chars().all(plain)) {
            return Err(format!(
                "`{}` is not a host name or IP address (e.g. `robots.lab`, `192.168.1.20`, \
                 `[fe80::1]`; no port, no scheme)",
                name.chars().take(80).collect::<String>()
            ));
        }
        self.hosts.push(n);
        Ok(self)
    }

    /// Also accepts pages of origin `origin` (`http://NAME[:PORT]` or `https://...`, as the
    /// browser sends it).
    pub fn allow_origin(mut self, origin: &str) -> Result<Access, String> {
        let o = origin.trim().trim_end_matches('/').to_ascii_lowercase();
        let rest = o
            .strip_prefix("http://")
            .or_else(|| o.strip_prefix("https://"));
        let ok = rest.is_some_and(|r| {
            !r.is_empty()
                && r.chars().all(|c| {
                    c.is_ascii_alphanumeric() || matches!(c, '-' | '.' | '_' | ':' | '[' | ']')
                })
        });
        if !ok || o.len() > MAX_ALLOWED_NAME {
            return Err(format!(
                "`{}` is not an origin (`http://NAME:PORT` or `https://NAME`, as the browser's \
                 address bar shows it, without a path)",
                origin.chars().take(80).collect::<String>()
            ));
        }
        self.origins.push(o);
        Ok(self)
    }

    /// The server bound `bind:port`: its port is the one `Host` must name, and a non-loopback
    /// bind address is allowed.
    pub(super) fn bound(mut self, bind: IpAddr, port: u16) -> Access {
        self.port = port;
        self.bind = (!bind.is_loopback()).then_some(bind);
        self
    }

    /// Whether `name` (lower case, no port) is one of the server's names.
    fn name_allowed(&self, name: &str) -> bool {
        if LOOPBACK_NAMES.contains(&name) || self.hosts.iter().any(|h| h == name) {
            return true;
        }
        let ip = name
            .strip_prefix('[')
            .and_then(|r| r.strip_suffix(']'))
            .unwrap_or(name)
            .parse::<IpAddr>();
        match (self.bind, ip) {
            (Some(b), Ok(ip)) if b.is_unspecified() => !ip.is_unspecified(),
            (Some(b), Ok(ip)) => b == ip,
            _ => false,
        }
    }

    /// Checks a `Host` value (`name[:port]`).
    pub fn check_host(&self, host: Option<&[u8]>) -> Result<(), Refusal> {
        let Some(host) = host.and_then(|h| std::str::from_utf8(h).ok()) else {
            return Err("no Host header");
        };
        if self.authority_allowed(host) {
            Ok(())
        } else {
            Err("this server answers only to its own address (Host): loopback or --allow-host")
        }
    }

    /// Whether `authority` (`name[:port]`) names this server.
    fn authority_allowed(&self, authority: &str) -> bool {
        let a = authority.trim().to_ascii_lowercase();
        let (name, port) = match a.rfind(':') {
            // `[::1]` alone has colons inside the brackets only.
            Some(i) if !a[i..].contains(']') => (&a[..i], a[i + 1..].parse::<u16>().ok()),
            _ => (a.as_str(), Some(80)),
        };
        port == Some(self.port) && self.name_allowed(name)
    }

    /// Checks an `Origin` value: none (not a web page) passes; else the server's own origin
    /// (`http://` + an allowed host with the port) or an allowed one.
    pub fn check_origin(&self, origin: Option<&[u8]>) -> Result<(), Refusal> {
        let Some(origin) = origin else {
            return Ok(());
        };
        let o = String::from_utf8_lossy(origin)
            .trim()
            .trim_end_matches('/')
            .to_ascii_lowercase();
        let own = o
            .strip_prefix("http://")
            .is_some_and(|a| self.authority_allowed(a));
        if own || self.origins.contains(&o) {
            Ok(())
        } else {
            Err("pages of another site may not use this server (Origin): see --allow-origin")
        }
    }

    /// Checks a request's `Host` and `Origin` headers.
    pub fn check(&self, headers: &[httparse::Header]) -> Result<(), Refusal> {
        let value = |name: &str| {
            headers
                .iter()
                .find(|h| h.name.eq_ignore_ascii_case(name))
                .map(|h| h.value)
        };
        self.check_host(value("host"))?;
        self.check_origin(value("origin"))
    }
}

/// A session's token: 128 bits from the operating system's random source, hex. Driving needs
/// it ([`super::hub`]).
#[derive(Clone)]
pub struct SessionToken(String);

impl SessionToken {
    /// A new random token.
    pub fn new() -> SessionToken {
        let mut bytes = [0u8; 16];
        getrandom::fill(&mut bytes).expect("the operating system's random source");
        SessionToken(bytes.iter().map(|b| format!("{b:02x}")).collect())
    }

    /// The token's text (32 hex digits).
    pub fn as_str(&self) -> &str {
        &self.0
    }

    /// Whether `presented` is the token (compared in constant time).
    pub fn matches(&self, presented: Option<&str>) -> bool {
        let Some(p) = presented else {
            return false;
        };
        let (a, b) = (self.0.as_bytes(), p.as_bytes());
        a.len() == b.len() && a.iter().zip(b).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
    }
}

impl Default for SessionToken {
    fn default() -> Self {
        SessionToken::new()
    }
}

impl std::fmt::Debug for SessionToken {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SessionToken(..)")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(port: u16) -> Access {
        Access::loopback().bound(IpAddr::V4(std::net::Ipv4Addr::LOCALHOST), port)
    }

    #[test]
    fn only_the_servers_own_host_and_origin() {
        let a = at(8642);
        for ok in [
            "127.0.0.1:8642",
            "localhost:8642",
            "[::1]:8642",
            "LocalHost:8642",
        ] {
            assert!(a.check_host(Some(ok.as_bytes())).is_ok(), "{ok}");
        }
        for bad in [
            "evil.example:8642",
            "127.0.0.1:9999",
            "127.0.0.1",
            "localhost.evil.example:8642",
            "",
        ] {
            assert!(a.check_host(Some(bad.as_bytes())).is_err(), "{bad}");
        }
        assert!(a.check_host(None).is_err());
        assert!(a.check_origin(None).is_ok(), "a program, not a page");
        assert!(a.check_origin(Some(b"http://127.0.0.1:8642")).is_ok());
        assert!(a.check_origin(Some(b"http://localhost:8642/")).is_ok());
        for bad in [
            "http://evil.example",
            "http://evil.example:8642",
            "null",
            "https://127.0.0.1:8642",
            "http://127.0.0.1:8643",
        ] {
            assert!(a.check_origin(Some(bad.as_bytes())).is_err(), "{bad}");
        }
        let b = at(8642)
            .allow_host("Robots.Lab")
            .unwrap()
            .allow_origin("https://dash.lab/")
            .unwrap();
        assert!(b.check_host(Some(b"robots.lab:8642")).is_ok());
        assert!(b.check_origin(Some(b"http://robots.lab:8642")).is_ok());
        assert!(b.check_origin(Some(b"https://dash.lab")).is_ok());
        assert!(Access::loopback().allow_host("a b").is_err());
        assert!(Access::loopback().allow_host("x:80").is_err());
        assert!(Access::loopback().allow_origin("dash.lab").is_err());
    }

    #[test]
    fn a_non_loopback_bind_allows_its_address() {
        let ip: IpAddr = "192.168.7.9".parse().unwrap();
        let a = Access::loopback().bound(ip, 80);
        assert!(
            a.check_host(Some(b"192.168.7.9")).is_ok(),
            "port 80 implied"
        );
        assert!(a.check_host(Some(b"192.168.7.10:80")).is_err());
        let any = Access::loopback().bound("0.0.0.0".parse().unwrap(), 8642);
        assert!(any.check_host(Some(b"10.0.0.3:8642")).is_ok());
        assert!(any.check_host(Some(b"evil.example:8642")).is_err());
    }

    #[test]
    fn tokens_are_random_and_compared_whole() {
        let (t, u) = (SessionToken::new(), SessionToken::new());
        assert_ne!(t.as_str(), u.as_str());
        assert_eq!(t.as_str().len(), 32);
        assert!(t.matches(Some(t.as_str())));
        assert!(!t.matches(Some(u.as_str())));
        assert!(!t.matches(Some(&t.as_str()[..31])));
        assert!(!t.matches(None));
    }
}

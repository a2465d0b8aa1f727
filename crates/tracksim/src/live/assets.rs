//! The page's files, embedded in the binary (nothing is read from disk or fetched at run time):
//! the page itself (`app.js` with its modules `hud.js`, `minimap.js`, `review.js`, `ruts.js`) and the
//! pinned three.js module build with its OrbitControls, vendored from the npm registry by
//! `scripts/update-three.sh` (version in [`THREE_VERSION`]).

/// three.js version vendored under `crates/tracksim/assets/vendor/` (npm package `three`).
pub const THREE_VERSION: &str = "0.187.0";

/// One embedded file: URL path, content type, bytes.
pub struct Asset {
    /// URL path, e.g. `/app.js`.
    pub path: &'static str,
    /// HTTP content type.
    pub content_type: &'static str,
    /// The file's bytes.
    pub bytes: &'static [u8],
}

const JS: &str = "text/javascript; charset=utf-8";

/// Every file the server may send. A request is answered only when its path is exactly one
/// of these: no request path ever reaches the file system.
pub const ASSETS: &[Asset] = &[
    Asset {
        path: "/",
        content_type: "text/html; charset=utf-8",
        bytes: include_bytes!("../../assets/index.html"),
    },
    Asset {
        path: "/app.js",
        content_type: JS,
        bytes: include_bytes!("../../assets/app.js"),
    },
    Asset {
        path: "/hud.js",
        content_type: JS,
        bytes: include_bytes!("../../assets/hud.js"),
    },
    Asset {
        path: "/ruts.js",
        content_type: JS,
        bytes: include_bytes!("../../assets/ruts.js"),
    },
    Asset {
        path: "/minimap.js",
        content_type: JS,
        bytes: include_bytes!("../../assets/minimap.js"),
    },
    Asset {
        path: "/review.js",
        content_type: JS,
        bytes: include_bytes!("../../assets/review.js"),
    },
    Asset {
        path: "/vendor/three.module.js",
        content_type: JS,
        bytes: include_bytes!("../../assets/vendor/three.module.js"),
    },
    Asset {
        path: "/vendor/three.core.js",
        content_type: JS,
        bytes: include_bytes!("../../assets/vendor/three.core.js"),
    },
    Asset {
        path: "/vendor/OrbitControls.js",
        content_type: JS,
        bytes: include_bytes!("../../assets/vendor/OrbitControls.js"),
    },
    Asset {
        path: "/vendor/LICENSE-three",
        content_type: "text/plain; charset=utf-8",
        bytes: include_bytes!("../../assets/vendor/LICENSE-three"),
    },
];

/// The embedded file at URL path `path` (the query string already removed), if any.
pub fn asset(path: &str) -> Option<&'static Asset> {
    let path = if path == "/index.html" { "/" } else { path };
    ASSETS.iter().find(|a| a.path == path)
}

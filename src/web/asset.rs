//! A file compiled into the program (a style sheet, a script, an icon) that a front end
//! serves under `/assets/NAME`, with the content type its name's ending says. Served only
//! from this table: a request names an asset, never a path on disk.

#[derive(Debug, Clone, Copy)]
pub struct Asset {
    /// The name after `/assets/`: `station.js`, `uplot.min.css`.
    pub name: &'static str,
    pub body: &'static [u8],
}

impl Asset {
    /// `Asset::new("station.js", include_bytes!("station.js"))`.
    pub const fn new(name: &'static str, body: &'static [u8]) -> Asset {
        Asset { name, body }
    }

    /// The content type a browser needs to use it (a script sent as text/plain is not run
    /// under `nosniff`).
    pub fn content_type(&self) -> &'static str {
        let ending = self.name.rsplit('.').next().unwrap_or_default();
        match ending {
            "css" => "text/css; charset=utf-8",
            "js" | "mjs" => "text/javascript; charset=utf-8",
            "html" => "text/html; charset=utf-8",
            "json" => "application/json",
            "svg" => "image/svg+xml",
            "png" => "image/png",
            "ico" => "image/x-icon",
            "woff2" => "font/woff2",
            "txt" => "text/plain; charset=utf-8",
            _ => "application/octet-stream",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_types_follow_the_name() {
        let t = |n| Asset::new(n, b"").content_type();
        assert_eq!(t("a.css"), "text/css; charset=utf-8");
        assert_eq!(t("uplot.min.js"), "text/javascript; charset=utf-8");
        assert_eq!(t("icon.svg"), "image/svg+xml");
        assert_eq!(t("noending"), "application/octet-stream");
    }
}

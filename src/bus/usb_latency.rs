//! The latency timer of a USB-serial adapter (FTDI and alike, 16 ms by default on Linux):
//! the adapter holds received bytes that long before passing them on, so one
//! request/reply exchange costs at least that much whatever the baud rate. Read from
//! `/sys/bus/usb-serial/devices/<tty>/latency_timer` (the root taken from
//! `$DRIVESCRIPT_SYSFS` when set, so it can be tested on a fake tree). Reads only; never
//! changes the timer.

use std::path::{Path, PathBuf};

/// The folder the kernel lists USB-serial ports in, under the sysfs root.
const USB_SERIAL: &str = "bus/usb-serial/devices";

/// The sysfs root: `$DRIVESCRIPT_SYSFS`, else `/sys`.
pub fn sysfs_root() -> PathBuf {
    std::env::var_os("DRIVESCRIPT_SYSFS").map_or_else(|| PathBuf::from("/sys"), PathBuf::from)
}

/// The file that holds `port`'s latency timer (`/dev/ttyUSB0` → `…/ttyUSB0/latency_timer`).
pub fn latency_timer_path(root: &Path, port: &str) -> Option<PathBuf> {
    let tty = Path::new(port).file_name()?;
    Some(root.join(USB_SERIAL).join(tty).join("latency_timer"))
}

/// `port`'s latency timer in milliseconds, where the system exposes it.
pub fn latency_timer_ms(root: &Path, port: &str) -> Option<u32> {
    let text = std::fs::read_to_string(latency_timer_path(root, port)?).ok()?;
    text.trim().parse().ok()
}

/// The ports the kernel lists as USB-serial (`/dev/ttyUSB0`), sorted.
pub fn usb_serial_ports(root: &Path) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(root.join(USB_SERIAL)) else {
        return Vec::new();
    };
    let mut ports: Vec<String> = entries
        .filter_map(Result::ok)
        .filter_map(|e| e.file_name().to_str().map(|n| format!("/dev/{n}")))
        .collect();
    ports.sort();
    ports
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_timer_is_read_from_the_ports_sysfs_folder() {
        let root = std::env::temp_dir().join(format!("drivescript-sysfs-{}", std::process::id()));
        let dir = root.join(USB_SERIAL).join("ttyUSB3");
        std::fs::create_dir_all(&dir).expect("fake sysfs");
        std::fs::write(dir.join("latency_timer"), "16\n").expect("timer");
        std::fs::create_dir_all(root.join(USB_SERIAL).join("ttyUSB1")).expect("a port without timer");
        assert_eq!(latency_timer_ms(&root, "/dev/ttyUSB3"), Some(16));
        assert_eq!(latency_timer_ms(&root, "/dev/ttyUSB1"), None);
        assert_eq!(latency_timer_ms(&root, "/dev/ttyS0"), None);
        assert_eq!(usb_serial_ports(&root), ["/dev/ttyUSB1", "/dev/ttyUSB3"]);
        let _ = std::fs::remove_dir_all(&root);
    }
}

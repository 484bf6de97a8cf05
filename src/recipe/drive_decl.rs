//! One drive a recipe declares under `drives:`: its name, its dictionary, its address in
//! its family's notation and, when it is not on the command line's connection, its own.
//! Plain data; the command line opens it.

/// `left: { drive: sd2, address: dnc:2 }`.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveDecl {
    /// The name steps use: `left.speed_actual`, `- enable_operation: left`.
    pub name: String,
    /// The built-in dictionary or family it names (`sd2`, `ct-unidrive-sp`).
    pub drive: String,
    /// The address in the family's notation (`dnc:2`, `3B`, `1.2`), also when the recipe
    /// wrote it with the family's address keys (`dnc_address: 2` is `dnc:2`); `None`: the
    /// family's default, or `--address`.
    pub address: Option<String>,
    /// Its own serial port, TCP serial server or CAN bus (`slcan:PATH`, `socketcan:IF`);
    /// all `None`: the command line's connection, shared with the other drives on it.
    pub port: Option<String>,
    pub tcp: Option<String>,
    pub can: Option<String>,
}

impl DriveDecl {
    /// Whether the drive uses the command line's connection.
    pub fn on_command_line_connection(&self) -> bool {
        self.port.is_none() && self.tcp.is_none() && self.can.is_none()
    }
}

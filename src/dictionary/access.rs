//! Who may read and write an object: `ro`, `rw`, `wo`. The drive layer refuses a write to a
//! read-only object before anything is sent; this module only answers the question.

use std::fmt;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Access {
    ReadOnly,
    ReadWrite,
    WriteOnly,
}

impl Access {
    pub const ALL: [Access; 3] = [Access::ReadOnly, Access::ReadWrite, Access::WriteOnly];

    /// The spelling in dictionary files: `ro`, `rw`, `wo`.
    pub fn id(self) -> &'static str {
        match self {
            Access::ReadOnly => "ro",
            Access::ReadWrite => "rw",
            Access::WriteOnly => "wo",
        }
    }

    pub fn from_id(id: &str) -> Option<Access> {
        Self::ALL.into_iter().find(|a| a.id() == id)
    }

    pub fn readable(self) -> bool {
        matches!(self, Access::ReadOnly | Access::ReadWrite)
    }

    pub fn writable(self) -> bool {
        matches!(self, Access::ReadWrite | Access::WriteOnly)
    }

    /// `read-only`, `read-write`, `write-only`: for messages.
    pub fn describe(self) -> &'static str {
        match self {
            Access::ReadOnly => "read-only",
            Access::ReadWrite => "read-write",
            Access::WriteOnly => "write-only",
        }
    }
}

impl fmt::Display for Access {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readable_and_writable() {
        assert!(Access::ReadOnly.readable() && !Access::ReadOnly.writable());
        assert!(Access::ReadWrite.readable() && Access::ReadWrite.writable());
        assert!(!Access::WriteOnly.readable() && Access::WriteOnly.writable());
        for a in Access::ALL {
            assert_eq!(Access::from_id(a.id()), Some(a));
        }
        assert_eq!(Access::from_id("RW"), None);
    }
}

//! Where a Modbus object lives, written the way manuals write it: `40001`/`400001`
//! (holding register 0 on the wire; the 1-based reference numbers of the "4xxxx" and
//! "3xxxx" tables), or the wire address with its table (`holding 0x1001`, `input 8`); a
//! 32-bit object sent low word first ends in ` low-word-first` (high word first is the
//! default; the specification fixes no order). Held in [`Address`]: the index is the wire
//! address, the subindex carries the table and the word order. Pure.

use crate::dictionary::{Address, AddressError};

const INPUT: u32 = 1;
const LOW_WORD_FIRST: u32 = 2;
const LOW_WORD_SUFFIX: &str = "low-word-first";

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Table {
    Holding,
    Input,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Register {
    pub table: Table,
    /// The 0-based address on the wire.
    pub address: u16,
    pub low_word_first: bool,
}

const NOTATION: &str = "write a Modbus register as a reference number (`40001` or `400001` for holding register 0, `30001`/`300001` for input register 0) or as its wire address with its table (`holding 0x1001`, `input 8`); add ` low-word-first` for a 32-bit value sent low word first";

impl Register {
    pub fn holding(address: u16) -> Register {
        Register {
            table: Table::Holding,
            address,
            low_word_first: false,
        }
    }

    pub fn of(address: &Address) -> Option<Register> {
        let Address::Indexed { index, subindex } = *address;
        (subindex & !(INPUT | LOW_WORD_FIRST) == 0).then_some(Register {
            table: if subindex & INPUT != 0 {
                Table::Input
            } else {
                Table::Holding
            },
            address: index,
            low_word_first: subindex & LOW_WORD_FIRST != 0,
        })
    }

    pub fn address(self) -> Address {
        let mut sub = 0;
        if self.table == Table::Input {
            sub |= INPUT;
        }
        if self.low_word_first {
            sub |= LOW_WORD_FIRST;
        }
        Address::indexed(self.address, sub)
    }

    /// `holding 0x1001 (404098)`: the wire address and the reference number manuals print.
    pub fn notation(self) -> String {
        let (name, prefix) = match self.table {
            Table::Holding => ("holding", 4),
            Table::Input => ("input", 3),
        };
        let number = u32::from(self.address) + 1;
        let reference = if number <= 9999 {
            format!("{prefix}{number:04}")
        } else {
            format!("{prefix}{number:05}")
        };
        let order = if self.low_word_first {
            format!(" {LOW_WORD_SUFFIX}")
        } else {
            String::new()
        };
        format!("{name} 0x{:04X} ({reference}){order}", self.address)
    }

    pub fn parse(text: &str) -> Result<Register, AddressError> {
        let t = text.trim();
        let (t, low_word_first) = match t.strip_suffix(LOW_WORD_SUFFIX) {
            Some(rest) => (rest.trim_end(), true),
            None => (t, false),
        };
        let bad = |why: String| AddressError::from(format!("`{text}`: {why}; {NOTATION}"));
        let (table, address) = if let Some((word, number)) = t.split_once(char::is_whitespace) {
            let table = match word {
                "holding" => Table::Holding,
                "input" => Table::Input,
                other => return Err(bad(format!("`{other}` is no register table (holding or input)"))),
            };
            let number = number.trim();
            let value = match number.strip_prefix("0x").or_else(|| number.strip_prefix("0X")) {
                Some(hex) => u32::from_str_radix(hex, 16),
                None => number.parse::<u32>(),
            };
            let address = value.ok().and_then(|v| u16::try_from(v).ok()).ok_or_else(|| {
                bad(format!(
                    "`{number}` is no wire address 0..=65535 (0x0000..=0xFFFF)"
                ))
            })?;
            (table, address)
        } else {
            if !t.bytes().all(|b| b.is_ascii_digit()) || !(5..=6).contains(&t.len()) {
                return Err(bad("no reference number of 5 or 6 digits".into()));
            }
            let table = match &t[..1] {
                "4" => Table::Holding,
                "3" => Table::Input,
                _ => {
                    return Err(bad(
                        "a reference number starts with 4 (holding) or 3 (input)".into()
                    ))
                }
            };
            let number: u32 = t[1..].parse().map_err(|_| bad("no number".into()))?;
            let address = number
                .checked_sub(1)
                .and_then(|n| u16::try_from(n).ok())
                .ok_or_else(|| bad(format!("reference {number} is outside 1..=65536")))?;
            (table, address)
        };
        Ok(Register {
            table,
            address,
            low_word_first,
        })
    }
}

/// The dictionary's reading of `address:` for the Modbus families.
pub fn parse_address(text: &str) -> Result<Address, AddressError> {
    Register::parse(text).map(Register::address)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_numbers_and_wire_addresses_name_the_same_registers() {
        let h = |address| Register::holding(address);
        assert_eq!(Register::parse("40001"), Ok(h(0)));
        assert_eq!(Register::parse("400001"), Ok(h(0)));
        assert_eq!(Register::parse("404098"), Ok(h(0x1001)));
        assert_eq!(Register::parse("holding 0x1001"), Ok(h(0x1001)));
        assert_eq!(Register::parse("holding 4097"), Ok(h(0x1001)));
        let input = Register::parse("30009").unwrap();
        assert_eq!((input.table, input.address), (Table::Input, 8));
        assert_eq!(Register::parse("input 8"), Ok(input));
        let low = Register::parse("holding 0x0010 low-word-first").unwrap();
        assert!(low.low_word_first);
        assert_eq!(Register::of(&low.address()), Some(low));
        assert_eq!(h(0x1001).notation(), "holding 0x1001 (44098)");
        assert_eq!(h(0).notation(), "holding 0x0000 (40001)");
        assert_eq!(input.notation(), "input 0x0008 (30009)");
        assert_eq!(low.notation(), "holding 0x0010 (40017) low-word-first");
        for text in [h(0xD000).notation(), input.notation(), low.notation()] {
            let back = text.split(" (").next().unwrap().to_string()
                + if text.ends_with("first") {
                    " low-word-first"
                } else {
                    ""
                };
            assert_eq!(Register::parse(&back).map(Register::notation), Ok(text));
        }
    }

    #[test]
    fn other_text_is_refused_with_the_notation() {
        for bad in [
            "40000",
            "50001",
            "4001",
            "coil 3",
            "holding 70000",
            "holding x",
            "",
            "465537",
        ] {
            let e = Register::parse(bad).unwrap_err().to_string();
            assert!(e.contains("reference number"), "{bad}: {e}");
        }
        assert!(Register::of(&Address::indexed(1, 4)).is_none());
    }
}

//! Lines of `key value value ...` over semihosting, numbers as hex (floats
//! as their IEEE bits, so nothing is lost and no `core::fmt` float code is
//! linked); run.sh turns them into JSON.

use crate::hio;

/// One line being built; longer lines are cut.
pub struct Line {
    buffer: [u8; 128],
    len: usize,
}

impl Line {
    /// A line starting with `key`.
    pub fn new(key: &str) -> Self {
        Self {
            buffer: [0; 128],
            len: 0,
        }
        .text(key)
    }

    /// Appends `text`.
    pub fn text(mut self, text: &str) -> Self {
        for &byte in text.as_bytes() {
            if let Some(slot) = self.buffer.get_mut(self.len) {
                *slot = byte;
                self.len += 1;
            }
        }
        self
    }

    /// Appends ` ` and `digits` hex digits of `x`.
    fn hex(mut self, x: u64, digits: u32) -> Self {
        self = self.text(" ");
        for k in (0..digits).rev() {
            let nibble = ((x >> (4 * k)) & 0xf) as u8;
            let c = if nibble < 10 {
                b'0' + nibble
            } else {
                b'a' + nibble - 10
            };
            if let Some(slot) = self.buffer.get_mut(self.len) {
                *slot = c;
                self.len += 1;
            }
        }
        self
    }

    /// Appends a u32 as 8 hex digits.
    pub fn u32(self, x: u32) -> Self {
        self.hex(x.into(), 8)
    }

    /// Appends an f32's bits as 8 hex digits.
    pub fn f32(self, x: f32) -> Self {
        self.hex(x.to_bits().into(), 8)
    }

    /// Appends an f64's bits as 16 hex digits.
    pub fn f64_bits(self, bits: u64) -> Self {
        self.hex(bits, 16)
    }

    /// Writes the line and a newline to the host's standard output.
    pub fn send(self) {
        if let Ok(mut out) = hio::hstdout() {
            let _ = out.write_all(&self.buffer[..self.len]);
            let _ = out.write_all(b"\n");
        }
    }
}

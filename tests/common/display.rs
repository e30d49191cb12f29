//! An X server for the viewer tests: a private Xvfb per test, stopped when the guard
//! drops. With no Xvfb installed the test fails saying how to install it — never a
//! silent skip.

use std::io::Read as _;
use std::process::{Child, Command, Stdio};

pub struct Xvfb {
    child: Child,
    /// The DISPLAY value, e.g. ":3".
    pub display: String,
}

impl Xvfb {
    pub fn start() -> Self {
        let mut child = match Command::new("Xvfb")
            // Xvfb picks a free display and writes its number to fd 1.
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1280x800x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
        {
            Ok(c) => c,
            Err(e) => panic!(
                "the viewer tests need Xvfb ({e}). On Debian/Ubuntu: \
                 sudo apt-get install -y xvfb (or run `sh .ci/setup`)"
            ),
        };
        let mut number = String::new();
        let mut stdout = child.stdout.take().expect("Xvfb stdout");
        let mut byte = [0u8; 1];
        while stdout.read(&mut byte).map(|n| n == 1).unwrap_or(false) && byte[0] != b'\n' {
            number.push(byte[0] as char);
        }
        assert!(
            !number.trim().is_empty(),
            "Xvfb did not report a display number"
        );
        Self {
            child,
            display: format!(":{}", number.trim()),
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

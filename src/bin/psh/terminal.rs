//! The terminal: standard output that survives a closed pipe, and progress bars.

/// Writes `text` to standard output; exits quietly (0) on a closed pipe, with 1 on other
/// write errors ([`out!`], [`outln!`]).
pub fn write_stdout(text: std::fmt::Arguments) {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    if let Err(e) = stdout.write_fmt(text).and_then(|()| stdout.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: standard output: {e}");
        std::process::exit(1);
    }
}

/// Progress drawn on stderr by indicatif when it is a terminal (hidden otherwise).
pub struct TerminalProgress(indicatif::ProgressBar);

impl TerminalProgress {
    pub fn new() -> Self {
        Self(indicatif::ProgressBar::hidden())
    }
}

impl psh::progress::Progress for TerminalProgress {
    fn start(&self, what: &str, total: u64) {
        self.0.reset();
        self.0
            .set_draw_target(indicatif::ProgressDrawTarget::stderr());
        self.0.set_length(total);
        self.0.set_position(0);
        // The template is a constant: it parses.
        if let Ok(style) =
            indicatif::ProgressStyle::with_template("{msg} {bar:40} {pos}/{len}, {eta} left")
        {
            self.0.set_style(style);
        }
        self.0.set_message(what.to_string());
    }

    fn advance(&self, n: u64) {
        self.0.inc(n);
    }

    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

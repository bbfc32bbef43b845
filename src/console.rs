//! Standard output and standard error as the command line writes them, never by a
//! panicking macro. A reader that has gone (a closed pipe: `areo sun … | head -1`) ends
//! the process at once, quietly, with status 141 — what a shell reports for a writer
//! killed by SIGPIPE, and what `yes | head -1` gives —; any other failure to write
//! (a full device, an I/O error) is an error naming standard output, exit 1. Standard
//! error is written as far as it can be: with nowhere left to report, a failure there
//! is dropped.

use std::io::Write;

use areo_scenario::Error;

/// The exit status of a writer whose reader has gone: 128 + SIGPIPE.
pub(crate) const CLOSED_PIPE: i32 = 141;

/// Writes `text` to standard output and flushes it, with what a terminal must not
/// receive raw (controls, bidirectional and invisible characters) shown as escapes
/// ([`areo_scenario::output::escape::console`]).
pub(crate) fn out(text: &str) -> Result<(), Error> {
    let text = areo_scenario::output::escape::console(text);
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(CLOSED_PIPE),
        Err(source) => Err(Error::Io { path: "(standard output)".into(), source }),
    }
}

/// Writes `text` to standard error, escaped as [`out`] escapes it; a failure there is
/// dropped.
pub(crate) fn err(text: &str) {
    let text = areo_scenario::output::escape::console(text);
    let mut stderr = std::io::stderr().lock();
    let _ = stderr.write_all(text.as_bytes()).and_then(|()| stderr.flush());
}

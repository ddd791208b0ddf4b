//! Why a command stopped: one error type for every command, shown on
//! stderr and, with `--json`, as the run's one JSON document.

use karigami::{Diagnostic, ErrorKind};
use serde::Serialize;

/// Why a command stopped. Its kind decides the exit status.
#[derive(Debug)]
pub(super) struct Error {
    pub kind: ErrorKind,
    /// What stderr shows, ending in a newline; empty once shown.
    pub text: String,
    /// The error in the JSON reports; `None` once shown. Boxed: an error
    /// travels in every `Result` of the CLI, which it should keep small.
    pub json: Option<Box<ErrorJson>>,
}

/// An error in a JSON report.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub(super) enum ErrorJson {
    /// An error in a recipe: where it is and what to change (null where
    /// the error has no such place).
    Recipe {
        class: &'static str,
        message: String,
        file: String,
        line: Option<usize>,
        column: Option<usize>,
        site: Option<String>,
        hint: Option<String>,
    },
    /// Any other error: a file, the command line, a refused --out.
    Plain {
        class: &'static str,
        message: String,
        #[serde(skip_serializing_if = "Option::is_none")]
        file: Option<String>,
        /// The command-line parser's whole message.
        #[serde(skip_serializing_if = "Option::is_none")]
        detail: Option<String>,
    },
}

/// The one JSON document of a run that stopped before any report.
#[derive(Serialize)]
struct Stopped<'a> {
    status: &'static str,
    error: &'a ErrorJson,
}

impl Error {
    /// An error without a place in a recipe: `error: MESSAGE`.
    pub(super) fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        let message = message.into();
        Self {
            kind,
            text: format!("error: {message}\n"),
            json: Some(Box::new(ErrorJson::Plain {
                class: kind.name(),
                message,
                file: None,
                detail: None,
            })),
        }
    }

    pub(super) fn usage(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Usage, message)
    }

    pub(super) fn io(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Io, message)
    }

    /// A file that could not be read.
    pub(super) fn unreadable(file: &str, e: &std::io::Error) -> Self {
        let mut error = Self::io(format!("cannot read {file}: {e}"));
        if let Some(ErrorJson::Plain { file: f, .. }) = error.json.as_deref_mut() {
            *f = Some(file.to_string());
        }
        error
    }

    /// A diagnostic against a recipe (`file` as messages name it, its
    /// text `source`), rendered with its place.
    pub(super) fn at(file: &str, source: &str, d: &Diagnostic) -> Self {
        let (line, column) = d.line_col(source).unzip();
        Self {
            kind: d.kind,
            text: d.render(file, source),
            json: Some(Box::new(ErrorJson::Recipe {
                class: d.kind.name(),
                message: d.message.clone(),
                file: file.to_string(),
                line,
                column,
                site: d.site.clone(),
                hint: d.hint.clone(),
            })),
        }
    }

    /// An error already shown where it happened (each failed recipe of a
    /// check or a batch): only its exit status is left to give.
    pub(super) fn shown(kind: ErrorKind) -> Self {
        Self {
            kind,
            text: String::new(),
            json: None,
        }
    }

    /// Show it only on stderr: the JSON report holds the results already.
    pub(super) fn text_only(mut self) -> Self {
        self.json = None;
        self
    }

    /// The message alone, without its kind, place or hint.
    pub(super) fn message(&self) -> String {
        match self.json.as_deref() {
            Some(ErrorJson::Recipe { message, .. } | ErrorJson::Plain { message, .. }) => {
                message.clone()
            }
            None => self.text.lines().next().unwrap_or("").to_string(),
        }
    }

    pub(super) fn exit_code(&self) -> i32 {
        self.kind.exit_code()
    }

    /// Show what is left to show: the text on stderr and, with `--json`,
    /// the error as the run's JSON document.
    pub(super) fn report(&self, json: bool) {
        err!("{}", self.text);
        if let (true, Some(error)) = (json, self.json.as_deref()) {
            print_json(&Stopped {
                status: "error",
                error,
            });
        }
    }
}

/// A build folder refused or not written (crates/folder): its sentence as
/// the crate says it, its kind (and so its exit status) the CLI's.
impl From<karigami_folder::Error> for Error {
    fn from(e: karigami_folder::Error) -> Self {
        use karigami_folder::Error as Folder;
        let kind = match &e {
            Folder::Io { .. } => ErrorKind::Io,
            Folder::NotAFolderName { .. } | Folder::MountPoint { .. } => {
                ErrorKind::OutNotAFolderName
            }
            Folder::UnderAFile { .. } => ErrorKind::OutUnderAFile,
            Folder::IsALink { .. } => ErrorKind::OutIsALink,
            Folder::IsAFile { .. } => ErrorKind::OutIsAFile,
            Folder::HoldsInput { .. } => ErrorKind::OutHoldsInput,
            Folder::HoldsCurrentFolder { .. } => ErrorKind::OutHoldsCurrentFolder,
            Folder::NotABuildFolder { .. } => ErrorKind::NotABuildFolder,
            Folder::OtherFiles { .. } | Folder::Appeared { .. } => {
                ErrorKind::BuildFolderHasOtherFiles
            }
            Folder::Locked { .. } => ErrorKind::OutLocked,
        };
        Self::new(kind, e.to_string())
    }
}

/// Print a JSON report on stdout. Its keys come out sorted, as they always
/// have (through `serde_json::Value`), whatever the order of the fields.
pub(super) fn print_json(report: &impl Serialize) {
    outln!("{}", json_text(report));
}

/// `print_json`'s text, for files.
pub(super) fn json_text(report: &impl Serialize) -> String {
    let value = serde_json::to_value(report).expect("a report serialises");
    serde_json::to_string_pretty(&value).expect("JSON is text")
}

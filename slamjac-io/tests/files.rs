//! Atomic writes and the output-path checks on real files.

use std::io::Write;
use std::path::Path;

use slamjac_io::{AtomicFile, PathError, Role, atomic, check_paths};

/// This process's umask, from `/proc/self/status` (reading it with
/// `umask(2)` would set it, under the other tests' feet).
#[cfg(target_os = "linux")]
fn umask() -> u32 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let line = status.lines().find(|l| l.starts_with("Umask:")).unwrap();
    u32::from_str_radix(line["Umask:".len()..].trim(), 8).unwrap()
}

#[cfg(unix)]
fn mode(path: &Path) -> u32 {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(path).unwrap().permissions().mode() & 0o777
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn nothing_reaches_the_destination_before_the_commit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.txt");
    std::fs::write(&path, "old").unwrap();
    let mut file = AtomicFile::create(&path).unwrap();
    file.write_all(b"new, half written").unwrap();
    assert_eq!(read(&path), "old");
    drop(file);
    assert_eq!(read(&path), "old", "a dropped write leaves the file");
    assert_eq!(listing(dir.path()), ["out.txt"], "and no temporary file");
    let mut file = AtomicFile::create(&path).unwrap();
    file.write_all(b"new").unwrap();
    file.commit().unwrap();
    assert_eq!(read(&path), "new");
    assert_eq!(listing(dir.path()), ["out.txt"]);
}

#[cfg(unix)]
#[test]
fn permissions_are_kept_and_links_followed_and_devices_written_in_place() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("target.txt");
    std::fs::write(&target, "old").unwrap();
    std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o640)).unwrap();
    let link = dir.path().join("link.txt");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    atomic::write(&link, "new").unwrap();
    assert!(link.is_symlink(), "the link stays a link");
    assert_eq!(read(&target), "new");
    let mode = std::fs::metadata(&target).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o640);
    atomic::write("/dev/null", "discarded").unwrap();
    let error = atomic::write(dir.path(), "x").unwrap_err();
    assert_eq!(error.kind(), std::io::ErrorKind::IsADirectory);
}

#[test]
fn an_output_naming_an_input_or_another_output_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.txt");
    std::fs::write(&input, "data").unwrap();
    let other_spelling = dir.path().join(".").join("in.txt");
    let hard_link = dir.path().join("hard.txt");
    std::fs::hard_link(&input, &hard_link).unwrap();
    let new = dir.path().join("new.svg");
    let new_again = dir.path().join("sub").join("..").join("new.svg");
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    let inputs = [Role::new("the input", &input)];
    for same in [&input, &other_spelling, &hard_link] {
        let error = check_paths(&inputs, &[Role::new("--output", same)]).unwrap_err();
        assert!(
            matches!(&error, PathError::Same { output, other, .. } if output == "--output" && other == "the input"),
            "{error}"
        );
        assert!(error.to_string().contains("refused before any work"));
    }
    let outputs = [Role::new("--plot", &new), Role::new("--output", &new_again)];
    let error = check_paths(&inputs, &outputs).unwrap_err().to_string();
    assert!(
        error.contains("--output names the same file as --plot"),
        "{error}"
    );
    assert!(!new.exists(), "the check writes nothing");
    check_paths(&inputs, &[Role::new("--output", &new)]).unwrap();
    let devices = [Role::new("--plot", Path::new("/dev/null")); 2];
    #[cfg(unix)]
    check_paths(&inputs, &devices).unwrap();
    let _ = devices;
    assert_eq!(listing(dir.path()), ["hard.txt", "in.txt", "sub"]);
}

#[test]
fn outputs_that_cannot_be_written_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no such folder").join("out.txt");
    let error = check_paths(&[], &[Role::new("--json", &missing)]).unwrap_err();
    assert!(matches!(error, PathError::NotWritable { .. }), "{error}");
    let error = check_paths(&[], &[Role::new("--json", dir.path())]).unwrap_err();
    assert!(error.to_string().contains("it is a directory"), "{error}");
    let odd = dir.path().join("a\nb\u{feff}").join("x");
    let error = check_paths(&[], &[Role::new("--json", &odd)])
        .unwrap_err()
        .to_string();
    assert!(error.contains("a\\nb\\ufeff"), "{error}");
}

/// Issue 28, class C: a dangling link's target is created (the link
/// stays, the target gets `0666` less the umask, never the link's 0777); a
/// link whose target's directory is missing, and a path ending in `/`, are
/// errors that write nothing.
#[cfg(target_os = "linux")]
#[test]
fn dangling_links_are_followed_and_new_files_get_0666_less_the_umask() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("other")).unwrap();
    let link = dir.path().join("o.json");
    std::os::unix::fs::symlink("other/new", &link).unwrap();
    atomic::write(&link, "new").unwrap();
    assert!(link.is_symlink(), "the link stays a link");
    let target = dir.path().join("other/new");
    assert_eq!(read(&target), "new");
    assert_eq!(mode(&target), 0o666 & !umask());
    let plain = dir.path().join("plain.txt");
    atomic::write(&plain, "x").unwrap();
    assert_eq!(mode(&plain), 0o666 & !umask());

    let nowhere = dir.path().join("nowhere.json");
    std::os::unix::fs::symlink("missing/new", &nowhere).unwrap();
    let error = atomic::write(&nowhere, "x").unwrap_err();
    assert_eq!(error.kind(), std::io::ErrorKind::NotFound);
    let message = error.to_string();
    assert!(
        message.contains("the symbolic link leads to") && message.contains("does not exist"),
        "{message}"
    );
    let error = check_paths(&[], &[Role::new("--output", &nowhere)]).unwrap_err();
    assert!(error.to_string().contains("cannot write here"), "{error}");

    let slash = dir.path().join("o2.json/");
    let error = atomic::write(&slash, "x").unwrap_err();
    assert_eq!(error.kind(), std::io::ErrorKind::InvalidInput);
    let error = check_paths(&[], &[Role::new("--output", &slash)]).unwrap_err();
    assert!(
        error.to_string().contains("does not name a file"),
        "{error}"
    );
    assert_eq!(
        listing(dir.path()),
        ["nowhere.json", "o.json", "other", "plain.txt"]
    );
    assert_eq!(listing(&dir.path().join("other")), ["new"]);
}

/// A dangling link names the file it would create: an output through it
/// and an output of that file are the same output.
#[cfg(unix)]
#[test]
fn a_dangling_link_to_another_output_is_that_output() {
    let dir = tempfile::tempdir().unwrap();
    let plot = dir.path().join("plot.svg");
    let link = dir.path().join("out.json");
    std::os::unix::fs::symlink("plot.svg", &link).unwrap();
    let error = check_paths(
        &[],
        &[Role::new("--plot", &plot), Role::new("--output", &link)],
    )
    .unwrap_err();
    assert!(
        error
            .to_string()
            .contains("--output names the same file as --plot"),
        "{error}"
    );
}

/// Issue 28, class E: a directory of files is written whole or not at all.
#[test]
fn a_tree_is_written_whole_or_not_at_all() {
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("project");
    let files = |name: &str| -> Vec<(std::path::PathBuf, Vec<u8>)> {
        vec![
            ("Cargo.toml".into(), b"[workspace]\n".to_vec()),
            (format!("{name}/src/lib.rs").into(), b"//! x\n".to_vec()),
        ]
    };
    // A component past 255 bytes fails after the first file is written.
    let long = "n".repeat(300);
    let error = atomic::write_tree(&project, &files(&long)).unwrap_err();
    assert!(error.to_string().contains(&long[..50]), "{error}");
    assert!(listing(dir.path()).is_empty(), "{:?}", listing(dir.path()));
    atomic::write_tree(&project, &files("crate")).unwrap();
    assert_eq!(read(&project.join("crate/src/lib.rs")), "//! x\n");
    assert_eq!(listing(dir.path()), ["project"]);
    #[cfg(target_os = "linux")]
    assert_eq!(mode(&project), 0o777 & !umask());
    // An existing empty directory is replaced, one with files refused.
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    atomic::write_tree(&empty, &files("c")).unwrap();
    assert_eq!(listing(&empty), ["Cargo.toml", "c"]);
    assert!(atomic::write_tree(&empty, &files("d")).is_err());
    assert_eq!(listing(&empty), ["Cargo.toml", "c"]);
    assert_eq!(listing(dir.path()), ["empty", "project"]);
}

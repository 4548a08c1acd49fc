//! Atomic writes and the output-path checks on real files.

use std::io::Write;
use std::path::Path;

use slamjac_io::{AtomicFile, PathError, Role, atomic, check_paths};

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

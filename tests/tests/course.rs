//! The course's one list of labs (`framework::labs::COURSE`) and what is derived from it agree:
//! every lab has its crate, its docs page, a row in the README's table and its key in the
//! reference; every lab crate is on the list; exercise numbers belong to their lab; the tests'
//! list of the labs' types (`for_each_lab!`) is the course.

use std::fs;

use framework::labs::COURSE;
use raylab_tests::workflow::{read, root};

#[test]
fn every_lab_of_the_course_has_its_crate_docs_and_readme_row() {
    let readme = read(&root().join("README.md"));
    for lab in COURSE {
        let name = format!("lab{:02}", lab.number);
        assert!(
            root().join("labs").join(&name).join("Cargo.toml").is_file(),
            "no crate labs/{name}"
        );
        assert!(
            root().join(format!("docs/{name}.md")).is_file(),
            "no docs/{name}.md"
        );
        assert!(
            readme.lines().any(|l| l.starts_with(&format!("| {name} |"))
                && l.contains(&format!("(docs/{name}.md)"))),
            "README.md's table has no row for {name} linking docs/{name}.md"
        );
        assert!(
            reference::KEYS.contains(&lab.number),
            "reference::KEYS lacks lab {}",
            lab.number
        );
        let exercises = (lab.exercises)();
        assert!(!exercises.is_empty(), "{name} has no exercises");
        for e in &exercises {
            assert!(
                e.id.starts_with(&format!("{}.", lab.number)),
                "{name}'s exercise {} is numbered for another lab",
                e.id
            );
        }
    }
}

#[test]
fn every_lab_crate_is_on_the_course_list() {
    for entry in fs::read_dir(root().join("labs")).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        let Some(number) = name.strip_prefix("lab").and_then(|n| n.parse::<u32>().ok()) else {
            continue;
        };
        assert!(
            framework::labs::lab(number).is_some(),
            "labs/{name} is not in framework::labs::COURSE"
        );
    }
}

#[test]
fn the_tests_list_of_lab_types_is_the_course() {
    let mut listed = Vec::new();
    macro_rules! list {
        ($number:expr, $module:ident, $contract:ident, $key:ident) => {
            assert_eq!(stringify!($module), format!("lab{:02}", $number));
            listed.push($number);
        };
    }
    raylab_tests::for_each_lab!(list);
    assert_eq!(
        listed,
        framework::labs::NUMBERS,
        "raylab_tests::for_each_lab lists other labs than framework::labs::COURSE"
    );
}

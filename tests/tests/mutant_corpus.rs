//! Every lab's checks reject the realistic mistakes of its mutant corpus, each in the exercise
//! it belongs to, and accept the alternative correct implementations.

use std::sync::Arc;

use framework::grading::Exercise;
use framework::labs::{lab01, lab02};
use raylab_tests::mutants::{self, Verdict};
use raylab_tests::{context, run_all};

/// Runs the corpus of one lab; returns the failures of the suite (empty when it discriminates).
fn judge<S: ?Sized>(
    lab: u32,
    exercises: &[Exercise<S>],
    variants: Vec<(&'static str, Verdict, Arc<S>)>,
) -> Vec<String> {
    let ctx = context(lab);
    let mut problems = Vec::new();
    let (mut wrong, mut rejected) = (0, 0);
    for (name, verdict, subject) in variants {
        let results = run_all(exercises, &subject, &ctx);
        match verdict {
            Verdict::Reject(id) => {
                wrong += 1;
                let r = &results
                    .iter()
                    .find(|(e, _)| *e == id)
                    .expect("known exercise")
                    .1;
                match r {
                    Err(message) => {
                        rejected += 1;
                        let first = message.lines().nth(1).unwrap_or_default();
                        println!("lab{lab:02} rejects  [{id}] {name}: {first}");
                    }
                    Ok(()) => problems.push(format!(
                        "lab {lab}: exercise {id} accepts the mistake '{name}'"
                    )),
                }
            }
            Verdict::Accept => {
                for (id, r) in &results {
                    match r {
                        Ok(()) => {}
                        Err(m) => problems.push(format!(
                            "lab {lab}: exercise {id} rejects the correct '{name}':\n{m}"
                        )),
                    }
                }
                println!("lab{lab:02} accepts  {name}");
            }
        }
    }
    println!(
        "lab{lab:02}: {rejected}/{wrong} mistakes rejected ({:.0}%)",
        100.0 * rejected as f64 / wrong.max(1) as f64
    );
    problems
}

#[test]
fn lab01_corpus() {
    let variants = mutants::lab01::variants()
        .into_iter()
        .map(|v| (v.name, v.verdict, Arc::new(v) as Arc<dyn lab01::CameraRays>))
        .collect();
    let problems = judge(1, &lab01::checks::exercises(), variants);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn lab02_corpus() {
    let variants = mutants::lab02::variants()
        .into_iter()
        .map(|v| (v.name, v.verdict, Arc::new(v) as Arc<dyn lab02::Lab02>))
        .collect();
    let problems = judge(2, &lab02::checks::exercises(), variants);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

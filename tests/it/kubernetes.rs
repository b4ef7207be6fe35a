//! The Kubernetes files of docs/sweep.md ("Kubernetes Indexed Job"), parsed: the fields the
//! page relies on are there and agree with each other. No cluster runs here; the Containerfile
//! is only read (no container engine either).

use crate::common;

use common::repo_path;
use serde_json::Value;

fn read(rel: &str) -> String {
    std::fs::read_to_string(repo_path(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

fn yaml(rel: &str) -> Value {
    serde_norway::from_str(&read(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// The one container of a Job's pod, and the pod's spec.
fn pod(job: &Value) -> (&Value, &Value) {
    let spec = &job["spec"]["template"]["spec"];
    let containers = spec["containers"].as_array().expect("containers");
    assert_eq!(containers.len(), 1);
    (spec, &containers[0])
}

/// The shell command a container runs (`/bin/sh -c ARG`).
fn shell(container: &Value) -> &str {
    assert_eq!(container["command"], serde_json::json!(["/bin/sh", "-c"]));
    container["args"][0].as_str().expect("one shell argument")
}

/// The claim the pod mounts at /parts.
fn parts_claim(spec: &Value, container: &Value) -> String {
    let mount = (container["volumeMounts"].as_array().unwrap().iter())
        .find(|m| m["mountPath"] == "/parts")
        .expect("a volume at /parts");
    let volume = (spec["volumes"].as_array().unwrap().iter())
        .find(|v| v["name"] == mount["name"])
        .expect("the mounted volume");
    volume["persistentVolumeClaim"]["claimName"]
        .as_str()
        .expect("a claim")
        .to_string()
}

#[test]
fn the_manifests_hold_what_the_docs_rely_on() {
    let pvc = yaml("deploy/kubernetes/parts-pvc.yaml");
    let sweep = yaml("deploy/kubernetes/sweep-job.yaml");
    let merge = yaml("deploy/kubernetes/merge-job.yaml");

    assert_eq!(pvc["kind"], "PersistentVolumeClaim");
    assert_eq!(pvc["apiVersion"], "v1");
    assert_eq!(pvc["spec"]["accessModes"], serde_json::json!(["ReadWriteMany"]));
    assert!(pvc["spec"]["resources"]["requests"]["storage"].is_string());
    let claim = pvc["metadata"]["name"].as_str().unwrap();

    for job in [&sweep, &merge] {
        assert_eq!(job["kind"], "Job");
        assert_eq!(job["apiVersion"], "batch/v1");
        let (spec, container) = pod(job);
        assert_eq!(spec["restartPolicy"], "Never");
        assert_eq!(parts_claim(spec, container), claim);
    }

    // the sweep: Indexed, retried per index, part JOB_COMPLETION_INDEX + 1 of PARTS = completions
    let s = &sweep["spec"];
    assert_eq!(s["completionMode"], "Indexed");
    assert!(s["backoffLimitPerIndex"].as_u64().is_some_and(|n| n >= 1), "{s}");
    assert!(
        s.get("backoffLimit").is_none(),
        "backoffLimit counts every index's failures"
    );
    let completions = s["completions"].as_u64().unwrap();
    assert!(s["parallelism"].as_u64().unwrap() <= completions);
    let (_, container) = pod(&sweep);
    let parts = (container["env"].as_array().unwrap().iter())
        .find(|e| e["name"] == "PARTS")
        .expect("PARTS");
    assert_eq!(parts["value"], completions.to_string());
    let command = shell(container);
    for word in [
        "k=$((JOB_COMPLETION_INDEX + 1))",
        "faze4 sweep --shard \"$k/$PARTS\"",
        "--out \"/parts/part_$k.csv\"",
        " -- shape",
    ] {
        assert!(command.contains(word), "{word} in {command}");
    }
    assert!(!command.contains('\n'), "one line: {command:?}");

    // the merge: the parts' tables on the volume, into it
    let (_, merge_container) = pod(&merge);
    assert_eq!(
        shell(merge_container),
        "exec faze4 sweep merge /parts/part_*.csv --out /parts/all.csv"
    );
    assert_eq!(container["image"], merge_container["image"]);
    assert_eq!(merge["spec"]["backoffLimit"], 0);

    // run.sh applies these files in order and gives up when a Job has failed
    let run = read("deploy/kubernetes/run.sh");
    let applied: Vec<&str> = run
        .lines()
        .filter_map(|l| l.strip_prefix("kubectl apply -f \"$here/"))
        .map(|l| l.trim_end_matches('"'))
        .collect();
    assert_eq!(applied, ["parts-pvc.yaml", "sweep-job.yaml", "merge-job.yaml"]);
    for name in ["faze4-sweep", "faze4-merge"] {
        assert!(run.contains(&format!("wait_for {name}")), "{name}");
    }
    assert_eq!(sweep["metadata"]["name"], "faze4-sweep");
    assert_eq!(merge["metadata"]["name"], "faze4-merge");
    assert!(run.contains("*\" Failed \"*)") && run.contains("timeout_s"));
    let syntax = std::process::Command::new("bash")
        .arg("-n")
        .arg(repo_path("deploy/kubernetes/run.sh"))
        .status()
        .unwrap();
    assert!(syntax.success(), "bash -n run.sh");

    // the page points to each file
    let docs = read("docs/sweep.md");
    for file in [
        "parts-pvc.yaml",
        "sweep-job.yaml",
        "merge-job.yaml",
        "run.sh",
        "Containerfile",
    ] {
        assert!(docs.contains(&format!("`{file}`")), "docs/sweep.md names {file}");
    }
}

#[test]
fn the_containerfile_builds_with_cargo_and_runs_in_slim_debian() {
    let text = read("Containerfile");
    let from: Vec<&str> = text.lines().filter(|l| l.starts_with("FROM ")).collect();
    assert_eq!(from.len(), 2, "{from:?}");
    assert!(
        from[0].contains("rust:") && from[0].ends_with(" AS build"),
        "{}",
        from[0]
    );
    assert!(from[1].contains("debian:") && from[1].contains("-slim"), "{}", from[1]);
    assert!(text.contains("cargo install --path . --locked --root /out"));
    assert!(text.contains("COPY --from=build /out/bin/faze4 /usr/local/bin/faze4"));
    let ignore = read(".containerignore");
    assert!(ignore.lines().any(|l| l == "target/"));
}

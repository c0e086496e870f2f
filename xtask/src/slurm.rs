//! `cargo xtask slurm-check`: the sweep's cluster path against a real SLURM. Installs Debian's
//! `slurm-wlm` and `munge` when missing (as root), starts a one-node cluster on localhost (munged,
//! slurmctld, slurmd; no systemd; a minimal `slurm.conf` in a temporary folder), submits a 4-point
//! sweep as an array of 2 with `sbatch`, waits for it, merges, checks the merged `results.csv`
//! equals a local run of the same sweep byte for byte, and stops the daemons it started.

use anyhow::{Context, Result, bail, ensure};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn have(cmd: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {cmd}")])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

fn sh(cmd: &mut Command) -> Result<String> {
    let o = cmd.output().with_context(|| format!("running {cmd:?}"))?;
    ensure!(
        o.status.success(),
        "{cmd:?} failed: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    Ok(String::from_utf8_lossy(&o.stdout).into_owned())
}

fn is_root() -> bool {
    sh(Command::new("id").arg("-u")).is_ok_and(|s| s.trim() == "0")
}

/// The daemons this check started, stopped (and waited for) when it ends, however it ends.
struct Daemons {
    children: Vec<(String, Child)>,
    pid_files: Vec<PathBuf>,
}

impl Drop for Daemons {
    fn drop(&mut self) {
        for (name, c) in self.children.iter_mut().rev() {
            let _ = c.kill();
            let _ = c.wait();
            eprintln!("stopped {name}");
        }
        for f in &self.pid_files {
            if let Ok(pid) = std::fs::read_to_string(f) {
                let _ = Command::new("kill").arg(pid.trim()).status();
            }
        }
    }
}

const SWEEP: &str = r#"{
  "name": "slurm-check",
  "description": "4 points of the seed comparison on 65^2: the cluster path's check, not a study.",
  "scene": "seed-65.json",
  "resolve": false,
  "parameters": [
    { "parameter": "conditions.rolling_velocity_m_s", "values": [0.01, 0.05] },
    { "parameter": "conditions.load_n", "values": [10, 20] }
  ]
}"#;

pub fn check(keep: bool, ehl: Option<PathBuf>) -> Result<()> {
    let t0 = Instant::now();
    if !(have("sbatch") && have("slurmctld") && have("slurmd") && have("munged")) {
        ensure!(is_root(), "slurm-wlm and munge are missing and installing them needs root");
        println!("installing slurm-wlm and munge (apt-get) ...");
        let env_ok = |c: &mut Command| -> Result<()> {
            sh(c.env("DEBIAN_FRONTEND", "noninteractive")).map(|_| ())
        };
        env_ok(Command::new("apt-get").args(["update", "-qq"]))?;
        env_ok(Command::new("apt-get").args(["install", "-y", "-qq", "slurm-wlm", "munge"]))?;
    }
    ensure!(is_root(), "the one-node cluster's daemons run as root here: run as root");
    let ehl = match ehl {
        Some(p) => {
            ensure!(p.is_file(), "--ehl {}: no such file", p.display());
            std::fs::canonicalize(&p)?
        }
        None => build_ehl()?,
    };
    let tmp = std::env::temp_dir().join(format!("ehl-slurm-check-{}", std::process::id()));
    std::fs::create_dir_all(&tmp)?;
    let result = run_check(&tmp, &ehl);
    if result.is_ok() && !keep {
        let _ = std::fs::remove_dir_all(&tmp);
    } else {
        eprintln!("left {} for inspection", tmp.display());
    }
    result?;
    println!("slurm-check passed in {:.0} s", t0.elapsed().as_secs_f64());
    Ok(())
}

fn build_ehl() -> Result<PathBuf> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    sh(Command::new(cargo).args(["build", "--release", "-q", "-p", "ehl-cli"]))?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let exe = root.join("target/release/ehl");
    ensure!(exe.is_file(), "{} not built", exe.display());
    Ok(exe)
}

fn run_check(tmp: &Path, ehl: &Path) -> Result<()> {
    // The sweep: 4 points on 65², checks on (they are part of the results).
    let mut scene: serde_json::Value =
        serde_json::from_str(&ehl_scene::builtin("seed")?.to_json())?;
    scene["name"] = "seed-65".into();
    scene["grid"] = serde_json::json!({"nx": 65, "ny": 65});
    std::fs::write(tmp.join("seed-65.json"), scene.to_string())?;
    let sweep = tmp.join("slurm-check.json");
    std::fs::write(&sweep, SWEEP)?;

    let host = sh(Command::new("hostname").arg("-s"))?.trim().to_string();
    let cpus = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    let conf = write_conf(tmp, &host, cpus)?;
    let mut daemons = Daemons { children: vec![], pid_files: vec![] };
    start_munge(tmp, &mut daemons)?;
    let slurm = |c: &mut Command| -> Result<String> { sh(c.env("SLURM_CONF", &conf)) };
    for (name, args) in
        [("slurmctld", vec!["-D", "-i", "-f"]), ("slurmd", vec!["-D", "-N", host.as_str(), "-f"])]
    {
        let log = std::fs::File::create(tmp.join(format!("{name}.out")))?;
        let child = Command::new(name)
            .args(&args)
            .arg(&conf)
            .env("SLURM_CONF", &conf)
            .stdout(log.try_clone()?)
            .stderr(log)
            .spawn()
            .with_context(|| format!("starting {name}"))?;
        daemons.children.push((name.into(), child));
        println!("started {name}");
        if name == "slurmctld" {
            std::thread::sleep(Duration::from_secs(2));
        }
    }
    // Wait for the node to come up.
    let t0 = Instant::now();
    loop {
        let s = slurm(Command::new("sinfo").args(["-h", "-o", "%T"]))
            .unwrap_or_default()
            .trim()
            .to_string();
        if s == "idle" || s == "mixed" || s == "allocated" {
            break;
        }
        if t0.elapsed() > Duration::from_secs(60) {
            bail!("the node did not come up (state `{s}`); see {}", tmp.display());
        }
        std::thread::sleep(Duration::from_millis(500));
    }
    println!("node {host} is up ({cpus} CPUs)");

    // The cluster path: plan 2 shards, sbatch, wait, merge.
    let cluster = tmp.join("cluster");
    sh(Command::new(ehl)
        .args(["sweep", "plan"])
        .arg(&sweep)
        .args(["--shards", "2", "--out"])
        .arg(&cluster))?;
    let out = slurm(Command::new("sbatch").arg("--parsable").arg(cluster.join("sweep.sbatch")))?;
    let job = out.trim().split(';').next().unwrap_or("").to_string();
    println!("submitted array job {job} (2 tasks)");
    let t0 = Instant::now();
    loop {
        let q = slurm(Command::new("squeue").args(["-h", "-j", &job, "-o", "%i %T"]))
            .unwrap_or_default();
        if q.trim().is_empty() {
            break;
        }
        if t0.elapsed() > Duration::from_secs(600) {
            bail!("job {job} still queued or running after 10 min:\n{q}");
        }
        std::thread::sleep(Duration::from_secs(1));
    }
    println!("job {job} done in {:.0} s", t0.elapsed().as_secs_f64());
    for k in 0..2 {
        let log = cluster.join(format!("slurm-{job}_{k}.out"));
        ensure!(log.is_file(), "task {k} wrote no log ({}): did it run?", log.display());
    }
    sh(Command::new(ehl).args(["sweep", "merge"]).arg(&cluster))?;

    // The same sweep locally.
    let local = tmp.join("local");
    sh(Command::new(ehl).arg("sweep").arg(&sweep).arg("--out").arg(&local))?;
    let a = std::fs::read_to_string(cluster.join("results.csv"))?;
    let b = std::fs::read_to_string(local.join("results.csv"))?;
    ensure!(
        a == b,
        "the merged SLURM results differ from the local run:\n--- slurm\n{a}\n--- local\n{b}"
    );
    println!(
        "merged results of the SLURM array equal the local run byte for byte ({} rows)",
        a.lines().count() - 1
    );
    drop(daemons);
    Ok(())
}

fn write_conf(tmp: &Path, host: &str, cpus: usize) -> Result<PathBuf> {
    for d in ["state", "spool"] {
        std::fs::create_dir_all(tmp.join(d))?;
    }
    let t = tmp.display();
    let conf = format!(
        "# A one-node cluster for `cargo xtask slurm-check` (temporary).\n\
         ClusterName=ehlcheck\n\
         SlurmctldHost={host}\n\
         SlurmctldPort=16817\n\
         SlurmdPort=16818\n\
         AuthType=auth/munge\n\
         CredType=cred/munge\n\
         SlurmUser=root\n\
         SlurmdUser=root\n\
         StateSaveLocation={t}/state\n\
         SlurmdSpoolDir={t}/spool\n\
         SlurmctldPidFile={t}/slurmctld.pid\n\
         SlurmdPidFile={t}/slurmd.pid\n\
         SlurmctldLogFile={t}/slurmctld.log\n\
         SlurmdLogFile={t}/slurmd.log\n\
         ProctrackType=proctrack/linuxproc\n\
         TaskPlugin=task/none\n\
         JobAcctGatherType=jobacct_gather/none\n\
         AccountingStorageType=accounting_storage/none\n\
         JobCompType=jobcomp/none\n\
         MpiDefault=none\n\
         SchedulerType=sched/builtin\n\
         SelectType=select/cons_tres\n\
         SelectTypeParameters=CR_CPU\n\
         ReturnToService=2\n\
         NodeName={host} CPUs={cpus} State=UNKNOWN\n\
         PartitionName=check Nodes={host} Default=YES MaxTime=INFINITE State=UP\n"
    );
    let f = tmp.join("slurm.conf");
    std::fs::write(&f, conf)?;
    // slurmd reads a cgroup.conf beside slurm.conf when present; none is needed here.
    Ok(f)
}

/// munged with a key of its own in the temporary folder and its socket where the Slurm munge
/// plugin looks (`/run/munge`), unless one is already running.
fn start_munge(tmp: &Path, daemons: &mut Daemons) -> Result<()> {
    let sock = Path::new("/run/munge/munge.socket.2");
    if sock.exists() && sh(Command::new("munge").arg("-n")).is_ok() {
        println!("using the running munged");
        return Ok(());
    }
    let key = tmp.join("munge.key");
    if !key.exists() {
        // 1024 random bytes, the key munged wants (mode 0400, owned by the user running it).
        let mut bytes = vec![0u8; 1024];
        use std::io::Read;
        std::fs::File::open("/dev/urandom")?.read_exact(&mut bytes)?;
        std::fs::write(&key, bytes)?;
        sh(Command::new("chmod").arg("0400").arg(&key))?;
    }
    std::fs::create_dir_all("/run/munge")?;
    let pid = tmp.join("munged.pid");
    let log = tmp.join("munged.log");
    let seed = tmp.join("munged.seed");
    sh(Command::new("munged")
        .arg("--force")
        .arg(format!("--key-file={}", key.display()))
        .arg(format!("--pid-file={}", pid.display()))
        .arg(format!("--log-file={}", log.display()))
        .arg(format!("--seed-file={}", seed.display()))
        .arg(format!("--socket={}", sock.display())))?;
    daemons.pid_files.push(pid);
    let t0 = Instant::now();
    while sh(Command::new("munge").arg("-n")).is_err() {
        if t0.elapsed() > Duration::from_secs(10) {
            bail!("munged did not start; see {}", log.display());
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    println!("started munged");
    Ok(())
}

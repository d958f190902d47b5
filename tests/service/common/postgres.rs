//! A throw-away PostgreSQL server for the tests: `initdb` in a temporary directory, a
//! server listening on a Unix socket in it only (no TCP port to collide on), one per test
//! binary, stopped and removed by a watchdog when the test process exits. Every test gets
//! a database of its own ([`PgCluster::new_database`]).
//!
//! Without PostgreSQL's server programs the PostgreSQL tests say so loudly and pass,
//! unless `BEARING_SIM_REQUIRE_POSTGRES=1` (set by `scripts/ci/test-all`, hence by CI), which
//! makes the absence a failure.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;

pub struct PgCluster {
    bin: PathBuf,
    socket_dir: PathBuf,
    /// Runs the server programs as this user (PostgreSQL refuses to run as root).
    run_as: Option<String>,
    port: u16,
    data: PathBuf,
    /// The server's options, for a start after a stop.
    opts: String,
}

/// The server of this test binary, started on first use; `None` (after a loud message)
/// when PostgreSQL is not installed and not required.
pub fn pg_cluster() -> Option<&'static PgCluster> {
    static CLUSTER: OnceLock<Result<PgCluster, String>> = OnceLock::new();
    match CLUSTER.get_or_init(PgCluster::start) {
        Ok(c) => Some(c),
        Err(why) => {
            let required = std::env::var("BEARING_SIM_REQUIRE_POSTGRES").as_deref() == Ok("1");
            if required {
                panic!("PostgreSQL is required (BEARING_SIM_REQUIRE_POSTGRES=1) but: {why}");
            }
            eprintln!(
                "\n*** POSTGRESQL TESTS NOT RUN: {why}.\n*** Install PostgreSQL's server \
                 (Debian: apt-get install postgresql) or run scripts/ci/test-all, which does.\n"
            );
            None
        }
    }
}

/// The directory holding `initdb` and `pg_ctl`: on the PATH, or Debian's versioned
/// directory (newest first).
fn find_bin() -> Option<PathBuf> {
    if let Ok(dir) = std::env::var("BEARING_SIM_PG_BIN") {
        return Some(PathBuf::from(dir));
    }
    let on_path = std::env::var_os("PATH").and_then(|p| {
        std::env::split_paths(&p).find(|d| d.join("initdb").is_file() && d.join("pg_ctl").is_file())
    });
    if on_path.is_some() {
        return on_path;
    }
    let mut versions: Vec<(u32, PathBuf)> = std::fs::read_dir("/usr/lib/postgresql")
        .ok()?
        .flatten()
        .filter_map(|e| {
            let v = e.file_name().to_str()?.parse::<u32>().ok()?;
            let bin = e.path().join("bin");
            bin.join("initdb").is_file().then_some((v, bin))
        })
        .collect();
    versions.sort();
    versions.pop().map(|(_, bin)| bin)
}

impl PgCluster {
    fn start() -> Result<PgCluster, String> {
        let bin = find_bin().ok_or("initdb and pg_ctl were not found")?;
        // SAFETY: geteuid has no preconditions and cannot fail.
        let root = unsafe { libc::geteuid() } == 0;
        let run_as = root.then(|| "postgres".to_string());
        // The server runs as `postgres` when we are root, so its directory must be where
        // that user can reach it: /tmp, not a TMPDIR under /root. Short, for the socket
        // path's 107-byte limit.
        let tmp = if root {
            PathBuf::from("/tmp")
        } else {
            std::env::temp_dir()
        };
        let id = uuid::Uuid::new_v4().simple().to_string();
        let base = tmp.join(format!("bearing-sim-pg-{}", &id[..12]));
        std::fs::create_dir_all(&base).map_err(|e| format!("temporary directory: {e}"))?;
        let data = base.join("data");
        let port = 5432;
        if let Some(user) = &run_as {
            let ok = Command::new("chown")
                .arg(user)
                .arg(&base)
                .status()
                .map(|s| s.success())
                .unwrap_or(false);
            if !ok {
                return Err(format!(
                    "running as root, and the directory could not be given to user {user:?} \
                     (PostgreSQL refuses to run as root)"
                ));
            }
        }
        let opts = format!(
            "-k '{}' -p {port} -c listen_addresses='' -c fsync=off -c synchronous_commit=off \
             -c full_page_writes=off -c max_connections=300",
            base.display()
        );
        let c = PgCluster {
            bin,
            socket_dir: base.clone(),
            run_as,
            port,
            data: data.clone(),
            opts,
        };
        // Armed first: whatever happens next, the directory goes when this process does.
        c.watch_for_exit(&data, &base);
        // Durability is not under test here: fsync off makes initdb and the suite fast.
        c.run(
            "initdb",
            &[
                "-D".as_ref(),
                data.as_os_str(),
                "-A".as_ref(),
                "trust".as_ref(),
                "-U".as_ref(),
                "postgres".as_ref(),
                "--no-sync".as_ref(),
                "-E".as_ref(),
                "UTF8".as_ref(),
            ],
        )?;
        c.start_server()?;
        Ok(c)
    }

    /// A server of the caller's own, which it may stop and start (the shared one of
    /// [`pg_cluster`] must stay up for the other tests); `None` as for [`pg_cluster`].
    pub fn own() -> Option<PgCluster> {
        pg_cluster()?;
        Some(PgCluster::start().expect("a second PostgreSQL server"))
    }

    /// Start the server (again, after [`PgCluster::stop`]) and wait until it accepts.
    pub fn start_server(&self) -> Result<(), String> {
        let log = self.socket_dir.join("server.log");
        self.run(
            "pg_ctl",
            &[
                "-D".as_ref(),
                self.data.as_os_str(),
                "-o".as_ref(),
                self.opts.as_ref(),
                "-l".as_ref(),
                log.as_os_str(),
                "-w".as_ref(),
                "start".as_ref(),
            ],
        )
    }

    /// The server's processes: the postmaster (first line of `postmaster.pid`) and its
    /// children.
    fn processes(&self) -> Vec<i32> {
        let pid_file = self.data.join("postmaster.pid");
        let text = std::fs::read_to_string(&pid_file).expect("postmaster.pid");
        let main: i32 = text.lines().next().unwrap().trim().parse().unwrap();
        let mut pids = vec![main];
        for entry in std::fs::read_dir("/proc").unwrap().flatten() {
            let Ok(pid) = entry.file_name().to_string_lossy().parse::<i32>() else {
                continue;
            };
            let stat = std::fs::read_to_string(entry.path().join("stat")).unwrap_or_default();
            // "pid (comm) state ppid ...": the fields after the last ')'
            let ppid = stat
                .rsplit_once(')')
                .and_then(|(_, rest)| rest.split_whitespace().nth(1))
                .and_then(|p| p.parse::<i32>().ok());
            if ppid == Some(main) {
                pids.push(pid);
            }
        }
        pids
    }

    /// Freeze the server (SIGSTOP to it and its children): connections are accepted and
    /// never answered, as with a host that went away.
    pub fn freeze(&self) {
        for pid in self.processes() {
            // SAFETY: kill has no memory preconditions; these are our server's processes.
            unsafe { libc::kill(pid, libc::SIGSTOP) };
        }
    }

    /// Let a frozen server run on.
    pub fn thaw(&self) {
        for pid in self.processes() {
            // SAFETY: as in `freeze`.
            unsafe { libc::kill(pid, libc::SIGCONT) };
        }
    }

    /// Stop the server (its clients' connections are cut at once). A fast shutdown, not an
    /// immediate one: with fsync and synchronous commit off, an immediate stop would lose
    /// the last commits, the schema's migrations among them.
    pub fn stop(&self) {
        self.run(
            "pg_ctl",
            &[
                "-D".as_ref(),
                self.data.as_os_str(),
                "-m".as_ref(),
                "fast".as_ref(),
                "-w".as_ref(),
                "stop".as_ref(),
            ],
        )
        .expect("pg_ctl stop");
    }

    /// Run one of the server programs (as the `postgres` user when we are root).
    fn run(&self, program: &str, args: &[&std::ffi::OsStr]) -> Result<(), String> {
        let exe = self.bin.join(program);
        let mut cmd = match &self.run_as {
            Some(user) => {
                let mut c = Command::new("runuser");
                c.args(["-u", user, "--"]).arg(&exe);
                c
            }
            None => Command::new(&exe),
        };
        // In a directory the server's user can read: PostgreSQL 15's programs fail when
        // they cannot resolve the working directory (a checkout under /root, mode 700).
        let out = cmd
            .args(args)
            .current_dir(&self.socket_dir)
            .stdin(Stdio::null())
            .output()
            .map_err(|e| format!("{program}: {e}"))?;
        if !out.status.success() {
            return Err(format!(
                "{program} failed: {}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        Ok(())
    }

    /// A detached shell that stops the server and removes its directory once this test
    /// process has exited (statics are never dropped, so nothing else would).
    fn watch_for_exit(&self, data: &Path, base: &Path) {
        let pg_ctl = self.bin.join("pg_ctl");
        let stop = match &self.run_as {
            Some(user) => format!(
                "runuser -u {user} -- '{}' -D '{}' -m immediate stop",
                pg_ctl.display(),
                data.display()
            ),
            None => format!(
                "'{}' -D '{}' -m immediate stop",
                pg_ctl.display(),
                data.display()
            ),
        };
        let script = format!(
            "while kill -0 {pid} 2>/dev/null; do sleep 0.5; done; {stop} >/dev/null 2>&1; rm -rf '{base}'",
            pid = std::process::id(),
            base = base.display()
        );
        let _ = Command::new("sh")
            .args(["-c", &script])
            .current_dir(base)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn();
    }

    /// The URL of a server database for user `postgres`.
    fn url(&self, db: &str) -> String {
        format!(
            "postgres://postgres@localhost:{}/{db}?host={}",
            self.port,
            self.socket_dir.display()
        )
    }

    /// A new, empty database; returns its URL.
    pub async fn new_database(&self) -> String {
        use sqlx::Connection;
        let name = format!("t_{}", uuid::Uuid::new_v4().simple());
        let mut admin = sqlx::PgConnection::connect(&self.url("postgres"))
            .await
            .expect("connect to the test server");
        sqlx::query(&format!("CREATE DATABASE {name}"))
            .execute(&mut admin)
            .await
            .expect("CREATE DATABASE");
        let _ = admin.close().await;
        self.url(&name)
    }
}

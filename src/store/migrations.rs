//! How both backends run their schema migrations (`migrations/sqlite/`, `migrations/postgres/`).

use sqlx::migrate::Migrator;

/// A backend's migrations, run so that a database a newer release has migrated further
/// still opens: an older node can restart (or an upgrade be rolled back) while newer nodes
/// run. Safe only while migrations are additive (docs/reference/scale-out.md); tested by
/// `tests/service/store_contract.rs`, `a_database_migrated_by_a_newer_release_still_opens`.
pub(super) fn additive(mut migrator: Migrator) -> Migrator {
    migrator.set_ignore_missing(true);
    migrator
}

-- The format of a job's stored input (src/store/model.rs, INPUT_FORMAT): workers claim
-- only the formats they can run. Every row stored before this column is format 1.
-- (migrations/sqlite/0004 on the embedded backend.)
ALTER TABLE jobs ADD COLUMN input_format BIGINT NOT NULL DEFAULT 1;

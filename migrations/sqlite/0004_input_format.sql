-- The format of a job's stored input (src/store/model.rs, INPUT_FORMAT): workers claim
-- only the formats they can run. Every row stored before this column is format 1.
ALTER TABLE jobs ADD COLUMN input_format INTEGER NOT NULL DEFAULT 1;

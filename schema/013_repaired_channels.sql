-- napkin catalogue, schema version 13: a repaired channel is kept beside the
-- recorded one (docs/formats.md "Salvage record").
--
-- result_salvage.repaired_samples: for a channel salvage repaired (action
-- inverted, swapped back or replaced), the whole repaired channel the result
-- was computed from, little-endian IEEE-754 binary64, in the unit and on the
-- time base of the recorded channel (raw_channels of the same test and slot,
-- whose samples are never changed); its good samples are the recorded ones.
-- NULL for an excluded channel, and for every row written before this
-- version (those results were computed from repaired channels not kept).
-- `napkin export --format channels` writes the channels a result was
-- computed from, `report` overlays the recorded and the repaired channel.

ALTER TABLE result_salvage ADD COLUMN repaired_samples BLOB
  CHECK (repaired_samples IS NULL OR length(repaired_samples) % 8 = 0);

/**
 * The camcore service from TypeScript, with the README's request bodies.
 *
 * Types come from openapi/openapi.json through openapi-typescript with its default options
 * (`npm run generate` writes src/api.d.ts); calls go through openapi-fetch and Node's fetch.
 *
 *   npm ci && npm run generate && npm run build && npm run example -- http://127.0.0.1:8000
 *
 * Prints one JSON line of numbers from the answers.
 */
import createClient from "openapi-fetch";

import type { components, paths } from "./api.js";

type Schemas = components["schemas"];

const baseUrl = process.argv[2] ?? process.env.CAMCORE_URL ?? "http://127.0.0.1:8000";

// The JSON operations also answer CSV (Accept: text/csv, ?format=csv) for spreadsheets, so their
// success type is "model or text"; a client that reads JSON says so, and gets the models.
const api = createClient<paths, "application/json">({ baseUrl });

// README: characteristic values of MS
const characteristics: Schemas["CharacteristicsRequest"] = { curve: { type: "named", name: "MS" } };
// README: a 101-row table of Makino's universal curve with MS's break points
const table: Schemas["TableRequest"] = {
  curve: { type: "universal", t: [0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1] },
  samples: 101,
};
// README: indexer sizing, the guide's example (6 stops, θh = 270°, 60 rpm; a 50 kg disc of Ø600 mm)
const sizing: Schemas["SizingRequest"] = {
  indexer: { stops: 6, indexing_angle_deg: 270, speed_rpm: 60 },
  load: {
    parts: [{ shape: "disc", mass_kg: 50, diameter_mm: 600 }],
    friction_coefficient: 0.1,
    friction_radius_mm: 200,
    service_factor: 1.5,
  },
};
// README: a roller cam, rise 20 mm (MS) / dwell / return / dwell
const profile: Schemas["ProfileRequest"] = {
  profile: {
    follower: { type: "roller", roller_radius_mm: 10 },
    base_radius_mm: 40,
    segments: [
      { type: "rise", angle_deg: 120, lift_mm: 20, curve: { type: "named", name: "MS" } },
      { type: "dwell", angle_deg: 60 },
      { type: "return", angle_deg: 120, lift_mm: 20 },
      { type: "dwell", angle_deg: 60 },
    ],
  },
  samples: 361,
};

/** The answer's data, or an Error with the service's sentence (4xx answers are ErrorAnswer). */
function data<T>(result: { data?: T; error?: Schemas["ErrorAnswer"] | unknown; response: Response }, what: string): T {
  if (result.data === undefined) {
    throw new Error(`${what}: HTTP ${result.response.status} ${JSON.stringify(result.error)}`);
  }
  return result.data;
}

const ms = data(await api.POST("/v1/curves/characteristics", { body: characteristics }), "characteristics");
const universal = data(await api.POST("/v1/curves/table", { body: table }), "table");
const sized = data(await api.POST("/v1/indexers/sizing", { body: sizing }), "sizing");
const cam = data(await api.POST("/v1/profiles", { body: profile }), "profile");
// a file: the table's CSV twin, read as text
const csv = data(
  await api.GET("/v1/curves/{name}/table.csv", {
    params: { path: { name: "MS" }, query: { samples: 11 } },
    parseAs: "text",
  }),
  "csv",
);

console.log(
  JSON.stringify({
    ms_vm: ms.vm,
    ms_t_vm: ms.t_vm,
    ms_am_abs: ms.am_abs,
    ms_t_am_abs: ms.t_am_abs,
    universal_rows: universal.s.length,
    universal_s_at_t_0_3: universal.s[30],
    sizing_inertia_kgm2: sized.inertia_kgm2,
    sizing_friction_torque_nm: sized.friction_torque_nm,
    profile_points: cam.cam_angle_deg.length,
    profile_max_pressure_angle_deg: cam.checks.max_pressure_angle_deg,
    csv_header: csv.split("\n")[0],
  }),
);

#!/usr/bin/env python3
"""Writes the committed seed corpus of wayfinder-fuzz (Tests/Fuzz/corpus/<target>/...) from the project's own
fixtures (Maps/Buildings, App/Samples/office-walk, Tests/Fixtures/range) and small hand-made inputs in the
formats the readers document. Run from the repository root: python3 Tests/Fuzz/make_corpus.py"""
import json, os, shutil, struct

root = 'Tests/Fuzz/corpus'
shutil.rmtree(root, ignore_errors=True)

def w(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, 'wb') as f:
        f.write(data if isinstance(data, bytes) else data.encode())

def read(path, mode='rb'):
    with open(path, mode) as f:
        return f.read()

# ---- map: the bundled building and two small maps (the MapsTests fixture's shape, and extensions)
w(f'{root}/map/wayfinder-office.json', read('Maps/Buildings/wayfinder-office.json'))
def room():
    return [{"from": [0, 0], "to": [10, 0]}, {"from": [10, 0], "to": [10, 4]},
            {"from": [10, 4], "to": [0, 4]}, {"from": [0, 4], "to": [0, 0]}]
two = {"formatVersion": 1, "id": "fixture", "name": "Fixture building", "compassHeadingOfMapNorthDeg": 350.9,
       "floors": [
           {"id": "1", "name": "Ground floor", "elevationMeters": 0, "walls": room(),
            "doors": [{"id": "d1", "position": [10, 2], "widthMeters": 0.9, "label": "East door"}],
            "signs": [{"id": "s1", "kind": "exit", "position": [0, 2], "facing": [1, 0], "widthMeters": 0.3,
                       "heightMeters": 0.21, "mountingHeightMeters": 2.3, "doubleSided": False}],
            "pointsOfInterest": [{"id": "poi-a", "name": "Room A", "category": "room", "position": [2, 2], "behindDoor": True}]},
           {"id": "2", "name": "Upper floor", "elevationMeters": 3.5, "walls": room(),
            "signs": [{"id": "s2", "kind": "exit", "position": [5, 4], "facing": [0, -1], "widthMeters": 0.31,
                       "heightMeters": 0.22, "doubleSided": True, "placement": "projecting", "positionAdjustmentMeters": 0.05}],
            "pointsOfInterest": [{"id": "poi-b", "name": "Room B", "category": "office", "position": [2.5, 1.5], "behindDoor": False}]}],
       "graph": {"nodes": [
           {"id": "a", "kind": "pointOfInterest", "floorId": "1", "position": [2, 2], "label": "Room A", "pointOfInterestId": "poi-a"},
           {"id": "c1", "kind": "control", "floorId": "1", "position": [5, 2]},
           {"id": "e1", "kind": "verticalLink", "floorId": "1", "position": [8, 2], "label": "Elevator", "verticalLink": "elevator"},
           {"id": "e2", "kind": "verticalLink", "floorId": "2", "position": [8, 2], "label": "Elevator", "verticalLink": "elevator"},
           {"id": "c2", "kind": "control", "floorId": "2", "position": [5, 2]},
           {"id": "b", "kind": "pointOfInterest", "floorId": "2", "position": [2.5, 2], "pointOfInterestId": "poi-b"}],
           "edges": [{"from": "a", "to": "c1", "throughDoor": True}, {"from": "c1", "to": "e1"}, {"from": "e1", "to": "e2"},
                     {"from": "e2", "to": "c2"}, {"from": "c2", "to": "b"}]}}
w(f'{root}/map/two-floors.json', json.dumps(two, indent=2))
tiny = {"$schema": "map-v1.schema.json", "formatVersion": 1, "id": "tiny", "name": "Tiny", "x-note": "extension member",
        "floors": [{"id": "G", "name": "G", "elevationMeters": -1.5,
                    "walls": [{"from": [0, 0], "to": [3, 0]}, {"from": [3, 0], "to": [3, 3]}],
                    "signs": [{"id": "x", "kind": "exit", "position": [1.5, 0], "facing": [0, 1], "widthMeters": 0.3, "heightMeters": 0.21}],
                    "pointsOfInterest": [{"id": "p", "name": "Caf\u00e9 \u2615", "category": "amenity", "position": [1, 1]}]}],
        "graph": {"nodes": [{"id": "n1", "kind": "pointOfInterest", "floorId": "G", "position": [1, 1], "pointOfInterestId": "p"},
                            {"id": "n2", "kind": "control", "floorId": "G", "position": [2, 1], "label": None}],
                  "edges": [{"from": "n1", "to": "n2"}]}}
w(f'{root}/map/tiny-extensions.json', json.dumps(tiny, ensure_ascii=False))

# ---- bundle: the start of the committed sample walk, and a hand-made one with every optional field
s = 'App/Samples/office-walk'
frames = read(f'{s}/frames.jsonl', 'r').splitlines()[:25]
tmax = json.loads(frames[-1])['t']
obs = [l for l in read(f'{s}/observations.jsonl', 'r').splitlines() if json.loads(l)['t'] <= tmax + 5][:12]
truth = read(f'{s}/truth.jsonl', 'r').splitlines()[:25]
d = f'{root}/bundle/office-walk-start'
w(f'{d}/session.json', read(f'{s}/session.json'))
w(f'{d}/frames.jsonl', "\n".join(frames) + "\n")
w(f'{d}/observations.jsonl', "\n".join(obs) + "\n")
w(f'{d}/truth.jsonl', "\n".join(truth) + "\n")
w(f'{d}/expected.jsonl', '{"text":"Exit sign ahead","notBefore":0.5,"notAfter":2.0}\n{"text":"Turn left"}\n')
d = f'{root}/bundle/arkit-like'
K = {"fx": 1450.5, "fy": 1450.5, "cx": 959.2, "cy": 718.9, "width": 1920, "height": 1440}
w(f'{d}/session.json', json.dumps({"formatVersion": 1, "device": "iPhone13,2", "appVersion": "1.0 (7)", "intrinsics": K,
                                                   "signHeightMeters": 0.21, "mapId": "wayfinder-office", "floorId": "1"}))
ident = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 1.4, -2.0, 1]
turned = [0, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1.0, 1.4, -2.5, 1]
fr = [{"t": 10.0, "cameraToWorld": ident, "tracking": "notAvailable", "intrinsics": K},
      {"t": 10.1, "cameraToWorld": ident, "tracking": "limited", "trackingReason": "relocalizing", "intrinsics": K,
       "image": "000001.jpg", "compassHeadingDeg": 359.9, "relativeAltitudeMeters": -0.2},
      {"t": 10.2, "cameraToWorld": turned, "tracking": "normal", "intrinsics": K, "image": "000002.jpg"}]
w(f'{d}/frames.jsonl', "\n".join(json.dumps(f) for f in fr) + "\n")
w(f'{d}/observations.jsonl',
  json.dumps({"t": 10.1, "kind": "landmark", "rangeMeters": 2.5, "bearingRad": -0.3, "score": 1, "source": "imported", "landmarkId": "7"}) + "\n"
  + json.dumps({"t": 10.1, "kind": "exit", "rangeMeters": 4.0, "bearingRad": 3.1, "score": 0.2}) + "\n")
w(f'{d}/images/000001.jpg', b'\xff\xd8\xff\xd9')

# ---- range-csv: the project fixture and a camera_to_world variant (CR LF, comment, blank line, empty optional)
w(f'{root}/range-csv/observations.csv', read('Tests/Fixtures/range/observations.csv'))
w(f'{root}/range-csv/camera-to-world.csv',
  "# comment line\r\nimage_height, image_width,fx,fy,cx,cy,camera_to_world,u_tl,v_tl,u_tr,v_tr,u_br,v_br,u_bl,v_bl,sign_height_m,sign_width_m\r\n"
  "1440,1920,1602,1602,960,720,0;-1;0;0;1;0;0;0;0;0;1;0;0;1.4;0;1,900,600,1000,600,1000,670,900,670,0.21,0.30\r\n\r\n"
  "1440,1920,1602,1602,960,720,1;0;0;0;0;1;0;0;0;0;1;0;0;1.4;0;1,700,500,800,505,798,575,702,570,0.21,\r\n")

# ---- inavigate: small folders (info.yml, walls BMP, mapFeatures YAML, navgraph.json)
def bmp(width, height, bpp, rows, topdown=False, palette=()):
    stride = ((bpp * width + 31) // 32) * 4
    off = 14 + 40 + 4 * len(palette)
    b = b'BM' + struct.pack('<IHHI', off + stride * height, 0, 0, off)
    b += struct.pack('<IiiHHIIiiII', 40, width, -height if topdown else height, 1, bpp, 0, stride * height, 2835, 2835, len(palette), 0)
    b += b''.join(bytes(p) for p in palette)
    for r in (range(height) if topdown else range(height - 1, -1, -1)):
        rb = rows(r)
        b += rb + bytes(stride - len(rb))
    return b
# 20 x 10 px room at 10 px/m: wall rows 0 and 9, wall columns 0 and 19, 8-bit gray palette
W, H = 20, 10
def room_row(r):
    return bytes([255] * W) if r in (0, H - 1) else bytes([255] + [0] * (W - 2) + [255])
walls = bmp(W, H, 8, room_row, palette=[(i, i, i, 0) for i in range(256)])
d = f'{root}/inavigate/one-floor'
w(f'{d}/info.yml', "%YAML:1.0\n---\nbuilding_name: Test Hall\nfloor:\n    id: 1\n    features_file: mapFeatures_1.yml\n"
  "    walls: walls_1.bmp\n    scale: 10\n\tangle_to_north: 9.1\n")
w(f'{d}/walls_1.bmp', walls)
w(f'{d}/mapFeatures_1.yml', "%YAML:1.0\nmap_feature:\n    id: 0\n    type: exit_sign\n    position: [1.0, 0.15]\n    normal: [0, 1]\n"
  "    height: 2.2\nmap_feature:\n    id: 1\n    type: exit_sign\n    position: [ 1.05 0.5 ]\n    normal: [ 1. 0. ]\n"
  "map_feature:\n    id: 2\n    type: door\n    position: [1, 1]\n")
w(f'{d}/navgraph.json', json.dumps({"nodes": {
    "1": {"id": 1, "type": "destination", "position": [5, 5], "floor": "1", "label": "kitchen", "isDoor": 1},
    "2": {"id": 2, "type": "control", "position": [10, 5], "floor": "1", "label": "2"},
    "3": {"id": 3, "type": "destination", "position": [15, 5], "floor": "1", "label": "Men's restroom", "isDoor": 0}},
    "weights": [[0, 1, 0], [1, 0, 2.5], [0, 2.5, 0]]}))
d = f'{root}/inavigate/two-floors'
w(f'{d}/floors/info.yml', "building_name: \"Two Storeys\"\nfloor:\n  id: 1\n  features_file: f1.yml\n  walls: w.bmp\n  scale: 10\n"
  "  angle_to_north: 0\nfloor:\n  id: 2\n  features_file: f2.yml\n  walls: w.bmp\n  scale: 10\n  angle_to_north: 0\n")
w(f'{d}/floors/w.bmp', walls)
w(f'{d}/floors/f1.yml', "map_feature:\n    type: exit_sign\n    position: [1.0, 0.15]\n    normal: [0, 1]\n")
w(f'{d}/floors/f2.yml', "# no signs on this floor\n")
w(f'{d}/floors/navgraph.json', json.dumps({"nodes": {
    "1": {"id": 1, "type": "link", "position": [5, 5], "floor": 1, "label": "Elevator"},
    "2": {"id": 2, "type": "link", "position": [5, 5], "floor": "2", "label": "elevator"},
    "3": {"id": 3, "type": "control", "position": [12, 5], "floor": "2", "label": ""},
    "4": {"id": 4, "type": "destination", "position": [15, 6], "floor": "1", "label": "Office 12", "isDoor": 1}},
    "weights": [[0, 0, 0, 1], [0, 0, 1, 0], [0, 1, 0, 0], [1, 0, 0, 0]]}))

# ---- inavigate-yaml / inavigate-bmp: the parts alone, every BMP depth the reader supports
w(f'{root}/inavigate-yaml/info.yml', read(f'{root}/inavigate/one-floor/info.yml'))
w(f'{root}/inavigate-yaml/mapFeatures.yml', read(f'{root}/inavigate/one-floor/mapFeatures_1.yml', 'r')
  + "scalar: 'quoted' # comment\r\nlist: [1e3,\t-2.5, 7]\n...\n")
w(f'{root}/inavigate-bmp/gray8-room.bmp', walls)
w(f'{root}/inavigate-bmp/bgr24-bottom-up.bmp', bmp(5, 3, 24, lambda r: bytes([255 * (r % 2)] * 15)))
w(f'{root}/inavigate-bmp/bgrx32-top-down.bmp', bmp(4, 4, 32, lambda r: bytes([0, 0, 255 * (r == 1), 0] * 4), topdown=True))
w(f'{root}/inavigate-bmp/mono1.bmp', bmp(13, 3, 1, lambda r: bytes([0b10101010, 0b11110000]), palette=[(0, 0, 0, 0), (255, 255, 255, 0)]))
w(f'{root}/inavigate-bmp/pal4.bmp', bmp(7, 2, 4, lambda r: bytes([0x01, 0x23, 0x45, 0x60]), palette=[(i * 16, i * 16, i * 16, 0) for i in range(7)]))

# ---- occam: small InvisibleMap recordings (column-major poses + grouped tag_data; row-major + flat tag_data)
def pose_cm(x, y, z): return [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, y, z, 1]
def tag(tx, ty, tz): return [1, 0, 0, tx, 0, 1, 0, ty, 0, 0, 1, tz, 0, 0, 0, 1]
occ = {"map_id": "floor_2 82489399050875", "pose_data": [
    {"id": 0, "timestamp": 100.0, "pose": pose_cm(0, 1.4, 0)},
    {"id": 1, "timestamp": 100.5, "pose": pose_cm(0.2, 1.4, -0.5)},
    {"id": 2, "timestamp": 100.5, "pose": pose_cm(0.2, 1.4, -0.5)},
    {"id": 3, "timestamp": 101.0, "pose": pose_cm(0.4, 1.41, -1.0)}],
    "tag_data": [[{"tag_id": 4, "pose_id": 1, "timestamp": 100.5, "tag_pose": tag(0.3, -0.2, 2.5),
                   "camera_intrinsics": [1590.1, 1590.1, 954.2, 718.3], "tag_corners_pixel_coordinates": [1, 2, 3, 4, 5, 6, 7, 8]}],
                 [{"tag_id": 4, "pose_id": 3, "timestamp": 101.0, "tag_pose": tag(0.3, -0.2, 2.0), "camera_intrinsics": [1590.1, 1590.1, 954.2, 718.3]},
                  {"tag_id": 9, "pose_id": 3, "timestamp": 101.0, "tag_pose": tag(-1.0, 0.1, -3.0)}]]}
w(f'{root}/occam/grouped.json', json.dumps(occ))
occ2 = {"pose_data": [{"id": 5, "timestamp": 1.0, "pose": [1, 0, 0, 0.5, 0, 1, 0, 1.2, 0, 0, 1, -0.3, 0, 0, 0, 1]},
                      {"id": 6, "timestamp": 1.5, "pose": [0, 0, 1, 0.7, 0, 1, 0, 1.2, -1, 0, 0, -0.4, 0, 0, 0, 1]}],
        "tag_data": [{"tag_id": 1, "pose_id": 6, "timestamp": 1.5, "tag_pose": tag(0, 0, 1.5), "camera_intrinsics": [1600, 1600, 960, 720]}]}
w(f'{root}/occam/flat-row-major.json', json.dumps(occ2))

// rsbaseline: velocity.report's tracker (internal/lidar/l5tracks, with its shipped defaults from
// config/tuning.defaults.json) run on roadscand's object lists, for roadscan's comparison
// (scripts/baseline/velocity-report.sh; docs/tracking.md, "Against velocity.report's tracker").
// It is built inside a clone of velocity.report (cmd/rsbaseline/main.go there): the tracker is an
// internal package. Input: roadscand --objects-out O --frames-out F of one run; each frame is one
// Update() at the frame's last time, each object one cluster (its centroid, the measurement the
// tracker uses; its oriented box). Output: per frame the track each object went to (the object a new
// track started from included: GetLastAssociations() leaves those empty) with the track's state, and
// every active track in roadscand's --tracks-out columns. Track numbers are given in order of first
// appearance (the tracker's ids are random UUIDs).
package main

import (
	"bufio"
	"encoding/csv"
	"flag"
	"fmt"
	"io"
	"math"
	"os"
	"sort"
	"strconv"
	"time"

	"github.com/banshee-data/velocity.report/internal/lidar/l4perception"
	"github.com/banshee-data/velocity.report/internal/lidar/l5tracks"
)

type row map[string]string

func readCSV(path string) ([]row, error) {
	f, err := os.Open(path)
	if err != nil {
		return nil, err
	}
	defer f.Close()
	r := csv.NewReader(bufio.NewReader(f))
	r.FieldsPerRecord = -1
	head, err := r.Read()
	if err != nil {
		return nil, err
	}
	var out []row
	for {
		rec, err := r.Read()
		if err == io.EOF {
			break
		}
		if err != nil {
			return nil, err
		}
		m := row{}
		for i, h := range head {
			if i < len(rec) {
				m[h] = rec[i]
			}
		}
		out = append(out, m)
	}
	return out, nil
}

func create(path string) *os.File {
	f, err := os.Create(path)
	if err != nil {
		fmt.Fprintln(os.Stderr, err)
		os.Exit(1)
	}
	return f
}

func f32(s string) float32 { v, _ := strconv.ParseFloat(s, 64); return float32(v) }
func f64(s string) float64 { v, _ := strconv.ParseFloat(s, 64); return v }

func main() {
	objPath := flag.String("objects", "", "roadscand --objects-out")
	framesPath := flag.String("frames", "", "roadscand --frames-out")
	assocPath := flag.String("assoc", "", "out: frame,object,track,state")
	tracksPath := flag.String("tracks", "", "out: tracks in roadscand --tracks-out columns")
	maxTracks := flag.Int("max-tracks", 0, "0: the shipped default")
	flag.Parse()
	frames, err := readCSV(*framesPath)
	if err != nil {
		fmt.Fprintln(os.Stderr, "frames:", err)
		os.Exit(1)
	}
	objs, err := readCSV(*objPath)
	if err != nil {
		fmt.Fprintln(os.Stderr, "objects:", err)
		os.Exit(1)
	}
	byFrame := map[string][]row{}
	for _, o := range objs {
		byFrame[o["frame"]] = append(byFrame[o["frame"]], o)
	}
	cfg := l5tracks.DefaultTrackerConfig()
	if *maxTracks > 0 {
		cfg.MaxTracks = *maxTracks
	}
	tr := l5tracks.NewTracker(cfg)
	num := map[string]int{}
	next := 1
	id := func(s string) int {
		if n, ok := num[s]; ok {
			return n
		}
		num[s] = next
		next++
		return num[s]
	}
	af := create(*assocPath)
	defer af.Close()
	aw := bufio.NewWriter(af)
	defer aw.Flush()
	fmt.Fprintln(aw, "frame,object,track,state")
	tf := create(*tracksPath)
	defer tf.Close()
	tw := bufio.NewWriter(tf)
	defer tw.Flush()
	fmt.Fprintln(tw, "frame,t,track,state,class,x,y,z,vx,vy,speed,heading,length,width,height,points,hits,misses,age,"+
		"cov_xx,cov_xy,cov_yy,site_x,site_y,site_z,site_vx,site_vy,site_heading")
	for _, fr := range frames {
		t := f64(fr["t_last"])
		ts := time.Unix(0, int64(math.Round(t*1e9)))
		objsF := byFrame[fr["frame"]]
		cl := make([]l5tracks.WorldCluster, len(objsF))
		for i, o := range objsF {
			zmin, zmax := f32(o["z_min"]), f32(o["z_max"])
			cl[i] = l5tracks.WorldCluster{
				ClusterID: int64(f64(o["object"])), SensorID: "roadscan", TSUnixNanos: ts.UnixNano(),
				CentroidX: f32(o["centroid_x"]), CentroidY: f32(o["centroid_y"]), CentroidZ: f32(o["centroid_z"]),
				BoundingBoxLength: f32(o["length"]), BoundingBoxWidth: f32(o["width"]), BoundingBoxHeight: zmax - zmin,
				PointsCount: int(f64(o["points"])), HeightP95: zmax,
				OBB: &l4perception.OrientedBoundingBox{CenterX: f32(o["x"]), CenterY: f32(o["y"]), CenterZ: zmin,
					Length: f32(o["length"]), Width: f32(o["width"]), Height: zmax - zmin, HeadingRad: f32(o["heading"])},
			}
		}
		tr.Update(cl, ts)
		assoc := tr.GetLastAssociations()
		// tracks started this frame, from the objects no track took (their start at this time, at the centroid)
		born := map[[2]float32]string{}
		for _, k := range tr.GetActiveTracks() {
			if k.StartUnixNanos == ts.UnixNano() && k.ObservationCount == 1 {
				born[[2]float32{k.X, k.Y}] = k.TrackID
			}
		}
		for i := range cl {
			tid := ""
			if i < len(assoc) {
				tid = assoc[i]
			}
			if tid == "" {
				tid = born[[2]float32{cl[i].CentroidX, cl[i].CentroidY}]
			}
			if tid == "" {
				continue
			}
			k := tr.GetTrack(tid)
			st := "tentative"
			if k != nil {
				st = string(k.TrackState)
			}
			fmt.Fprintf(aw, "%s,%s,%d,%s\n", fr["frame"], objsF[i]["object"], id(tid), st)
		}
		act := tr.GetActiveTracks()
		sort.Slice(act, func(a, b int) bool { return id(act[a].TrackID) < id(act[b].TrackID) })
		for _, k := range act {
			sp := math.Hypot(float64(k.VX), float64(k.VY))
			fmt.Fprintf(tw, "%s,%.6f,%d,%s,unknown,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.4f,%.2f,%.2f,%.2f,0,%d,%d,%.3f,%.4f,%.4f,%.4f,,,,,,\n",
				fr["frame"], t, id(k.TrackID), string(k.TrackState), k.X, k.Y, k.LatestZ, k.VX, k.VY, sp, k.OBBHeadingRad,
				k.OBBLength, k.OBBWidth, k.OBBHeight, k.Hits, k.Misses, float64(ts.UnixNano()-k.StartUnixNanos)/1e9,
				k.P[0], k.P[1], k.P[5])
		}
	}
}
